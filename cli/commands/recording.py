"""turtlectl's Recording and Foxglove commands: record, info, play, recover, foxglove.

Recordings (cli.recording) and the Foxglove bridge (cli.foxglove) are imported inside each
command: MCAP and the Foxglove SDK load only for these."""

from __future__ import annotations

import sys
from pathlib import Path

import typer

from turtlectl.cli import args
from turtlectl.cli.commands.options import (
    ConnectOption,
    DomainOption,
    ExitOnLossOption,
    JsonOption,
    completer,
    format,
    result,
)
from turtlectl.runtime.client.errors import BadInput
from turtlectl.runtime.client.sigint import stop_on_signals


def record(
    topics: list[str] = typer.Argument(
        None,
        metavar="[TOPIC]...",
        autocompletion=completer("topics"),
        help="Key expressions to record, e.g. robot/status turtle1/*.",
    ),
    all_topics: bool = typer.Option(False, "-a", "--all", help="Record every topic (streams and feedback)."),
    output: Path | None = typer.Option(
        None, "-o", "--output", help="The MCAP file to write (must not exist).  [default: turtlectl_<date>-<time>.mcap]"
    ),
    duration: float | None = typer.Option(None, "--duration", min=0.1, help="Stop after S seconds."),
    exclude: list[str] = typer.Option(
        [], "--exclude", metavar="KEY_EXPR", help="Leave out keys matching this (repeatable)."
    ),
    scene: bool = typer.Option(
        False,
        "--scene",
        help="Also record the Foxglove 3D scene, and the log records for its Log panel (as `turtlectl foxglove` serves them).",
    ),
    profile: str = typer.Option(
        "turtlectl",
        "--profile",
        metavar="PROFILE",
        help="turtlectl: turtlectl's own MCAP file (JSON, Foxglove opens it); ros2: a ROS 2 bag, a folder as `ros2 bag record` writes it (MCAP, CDR; needs the ros2 extra).",
    ),
    exit_on_loss: bool = ExitOnLossOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Record topics into an MCAP file that Foxglove opens, as `ros2 bag record`.

    Each message keeps its receive time, its own stamp, its key and its type.  Ctrl-C or
    SIGTERM finishes the file; if the recorder is killed, at most the last second is lost.  A
    lost router is said on stderr and waited for (one line when it is back), and the time
    without it is marked in the file (`turtlectl info` lists it as a gap); --exit-on-loss
    finishes the file and exits with code 3 instead.

    With --profile ros2 the recording is a ROS 2 bag (a folder: OUT/OUT.mcap and
    metadata.yaml) that `ros2 bag play` and the rosbags library read: topics as ROS names,
    turtlectl's types as their ROS 2 types (docs/how-to/ros2-bags.md); a topic whose type has
    no ROS 2 type is left out, said once.

    Example: turtlectl record -a -o run.mcap;  turtlectl record -a --profile ros2 -o run_bag
    """
    from turtlectl.cli.recording import record as recording
    from turtlectl.cli.recording.bag import refuse_existing
    from turtlectl.cli.version import version

    args.finite_option(duration, "--duration")
    if profile not in ("turtlectl", "ros2"):
        raise BadInput(f"--profile {profile!r}: turtlectl (the default) or ros2")
    ros2 = "ros2" if profile == "ros2" else ""
    if ros2 and scene:
        raise BadInput("--scene is drawn for Foxglove in turtlectl's own recordings: not with --profile ros2")
    if ros2:
        from turtlectl.cli.recording.ros2bag import require

        require()
    keys, excluded = recording.keys_to_record(topics or [], all_topics, exclude)
    path = output or recording.default_path(profile=ros2)
    refuse_existing(path)
    with stop_on_signals() as stop:
        live = sys.stderr.isatty()
        typer.echo(
            f"recording {', '.join(keys)} into {path}" + (f" (not {', '.join(excluded)})" if excluded else ""), err=True
        )
        last = None
        made = f"turtlectl {version()}"
        for item in recording.record(
            connect, domain, keys, excluded, path, duration, stop, made, scene, exit_on_loss, ros2
        ):
            if isinstance(item, str):  # the router lost, or back
                typer.echo(("\r\033[K" if live else "") + item, err=True)
                continue
            last = item
            if live and not last.done:
                typer.echo(
                    "\r\033[K" + format.recording_line(last.elapsed, last.messages, last.size), nl=False, err=True
                )
        if live:
            typer.echo("\r\033[K", nl=False, err=True)
    if last is not None:
        result(f"recorded {last.messages} messages in {last.elapsed:.1f} s into {path} ({format.size_text(last.size)})")


def info(
    file: Path = typer.Argument(..., metavar="FILE", help="A recording (MCAP file), or a ROS 2 bag (its folder)."),
    json: bool = JsonOption,
) -> None:
    """What a recording holds, as `ros2 bag info`: size, duration, start and end, messages per
    topic with type, rate and encoding, whether the recorder closed the file, and the gaps
    (each time the recorder had no router, with its times and duration).

    Example: turtlectl info run.mcap
    """
    from turtlectl.cli.recording.reading import Recording

    details = Recording(file).info()
    result(format.info_json(details) if json else format.info_text(details))


def play(
    file: Path = typer.Argument(..., metavar="FILE", help="A recording (MCAP file), or a ROS 2 bag (its folder)."),
    rate: float = typer.Option(1.0, "--rate", min=0.01, help="Speed factor (2 = twice as fast)."),
    loop: bool = typer.Option(False, "--loop", help="Play again and again until Ctrl-C."),
    start_offset: float = typer.Option(0.0, "--start-offset", min=0.0, help="Start S seconds into the recording."),
    topics: list[str] = typer.Option([], "--topics", metavar="KEY", help="Play only this key (repeatable)."),
    remap: list[str] = typer.Option(
        [], "--remap", metavar="OLD:=NEW", help="Publish OLD's messages on NEW (repeatable)."
    ),
    keep_stamps: bool = typer.Option(
        False, "--keep-stamps", help="Keep the recorded stamps (default: stamp when sent)."
    ),
    clock: float | None = typer.Option(
        None,
        "--clock",
        min=1.0,
        max=1000.0,
        metavar="HZ",
        help="Also publish the recording's time on `clock` HZ times a second (ros2 bag play --clock), for nodes run with --use-sim-time; messages stamped as recorded.",
    ),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Publish a recording again, each message at its recorded time (divided by --rate), as
    `ros2 bag play`.  On a terminal, space pauses and resumes; Ctrl-C stops (exit code 0).

    Example: turtlectl play run.mcap --rate 2
    """
    from turtlectl.cli.recording import play as player
    from turtlectl.cli.recording.reading import Recording

    args.finite_option(rate, "--rate")
    args.finite_option(start_offset, "--start-offset")
    remaps = player.parse_remaps(remap)
    keys = [client_key(t) for t in topics] or None
    recording = Recording(file)
    if not recording.closed:
        from turtlectl.cli.recording.recover import hint

        typer.echo(
            f"warning: {file} was not closed (the recorder was killed?): playing what is complete; {hint(file)}",
            err=True,
        )
    for topic, ros_type in recording.unmapped().items():
        typer.echo(
            f"warning: {topic}: {ros_type} has no turtlectl type: played as its CDR bytes, not as a message", err=True
        )
    with stop_on_signals() as stop:
        live = sys.stdin.isatty() and sys.stderr.isatty()
        played = 0
        shown = ""
        with player.space_toggles(live) as paused:
            for item in player.play(
                connect,
                domain,
                recording,
                rate,
                start_offset,
                keys,
                remaps,
                keep_stamps,
                loop,
                paused,
                stop.is_set,
                clock,
            ):
                played += not item.paused
                state = "paused" if item.paused else "playing"
                if live and (state != shown or item.index % 25 == 0 or item.index + 1 == item.total):
                    shown = state
                    typer.echo(
                        f"\r\033[K{state} {item.offset:8.2f} s  {item.index + 1}/{item.total}"
                        + (f"  loop {item.loop + 1}" if loop else "")
                        + "  (space: pause)",
                        nl=False,
                        err=True,
                    )
        if live:
            typer.echo("\r\033[K", nl=False, err=True)
    result(f"played {played} messages from {file}")


def recover(
    file: Path = typer.Argument(..., metavar="FILE", help="A recording the recorder did not finish (MCAP file)."),
    output: Path | None = typer.Option(
        None, "-o", "--output", help="The file to write (must not exist).  [default: FILE-recovered.mcap]"
    ),
) -> None:
    """Write a complete, indexed copy of a recording that was not closed (the recorder was
    killed), as `mcap recover` and `ros2 bag reindex`: everything readable is kept, the file
    itself is left as it is.

    Example: turtlectl recover run.mcap   (writes run-recovered.mcap)
    """
    from turtlectl.cli.recording.recover import recover as recover_file
    from turtlectl.cli.recording.recover import text

    result(text(recover_file(file, output)))


def foxglove(
    port: int = typer.Option(8765, "--port", min=0, max=65535, help="WebSocket port (0: any free one)."),
    host: str = typer.Option("127.0.0.1", "--host", help="Address to listen on (loopback by default)."),
    layout: Path | None = typer.Option(None, "--layout", help="Write the Foxglove layout file here and exit."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Serve the running system to the Foxglove app (open the printed URL, or connect the app
    to ws://HOST:PORT): every topic, a ready-made 3D scene (world, obstacles, turtle, trail,
    scan, goal), every node's log on `log` for the Log panel, and navigate_to, cancel, reset and
    teleport as services.

    Example: turtlectl foxglove   (then in Foxglove: Open connection, ws://127.0.0.1:8765)
    """
    from importlib import resources

    if layout is not None:
        text = resources.files("turtlectl.cli.foxglove").joinpath("foxglove_layout.json").read_text()
        try:
            layout.write_text(text)
        except OSError as exc:
            raise BadInput(f"cannot write {layout}: {exc.strerror or exc}") from None
        result(f"wrote {layout}: in Foxglove, Layouts > Import from file")
        return
    import ipaddress

    try:
        address = str(ipaddress.ip_address(host))
    except ValueError:
        raise BadInput(f"--host {host!r} is not an IP address (e.g. 127.0.0.1)") from None
    from turtlectl.cli.foxglove import bridge

    with stop_on_signals() as stop:

        def started(server) -> None:
            where = f"ws://{address}:{server.port}"
            typer.echo(f"serving Foxglove on {where}; open {server.app_url()} or connect the app to {where}", err=True)
            if not ipaddress.ip_address(address).is_loopback:
                typer.echo(
                    f"warning: anyone who can reach {address}:{server.port} sees the robot and can send it goals",
                    err=True,
                )

        for _ in bridge.serve(connect, domain, address, port, stop, started):
            pass


def client_key(text: str) -> str:
    from turtlectl.runtime.client.session import check_key

    return check_key(text, publish=True)


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.command()(record)
    app.command()(info)
    app.command()(play)
    app.command()(recover)
    app.command()(foxglove)
