"""``turtlectl``: the command-line interface (Typer).

Commands are thin: they parse options, call logic in cli.* that never prints,
and print what it returns.  ``main`` is the one place that turns a CliError
into a message on stderr and an exit code.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Optional

import typer

from cli import client, format
from cli.errors import CliError, ExitCode
from cli.launchfile import LaunchFileError, load_launch
from cli.supervisor.manager import Supervisor
from cli.supervisor.printer import Printer
from messages import Cancel, Reset, TeleportAbsolute, keys
from nodes.session import CONNECT_ENV, DEFAULT_ENDPOINT, DEFAULT_PORT

EXIT_CODES = """
Exit codes: 0 success; 1 ran but did not succeed (goal not reached, a required
node died); 2 bad input (arguments, launch file); 3 nothing to talk to (no
router, no navigator, no message); 4 launch could not start (port in use);
130 interrupted (goto).
"""

app = typer.Typer(
    name="turtlectl",
    help="A turtle robot over Zenoh, the ROS 2 way: launch, goto, cancel, teleport, reset, echo." + EXIT_CODES,
    no_args_is_help=True,
    add_completion=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,  # plain click output: usage errors stay short, help is greppable
    context_settings={"help_option_names": ["-h", "--help"]},
)

PACKAGED_LAUNCH = Path(__file__).resolve().parent / "launch.toml"

ConnectOption = typer.Option(
    DEFAULT_ENDPOINT, "--connect", envvar=CONNECT_ENV, help="Router endpoint of the system to talk to."
)


def default_launch_file() -> Path:
    """./launch.toml if there is one, else the packaged default."""
    local = Path("launch.toml")
    return local if local.is_file() else PACKAGED_LAUNCH


@app.command()
def launch(
    file: Optional[Path] = typer.Argument(None, metavar="[FILE]", help="Launch file (default: ./launch.toml, else the packaged one)."),
    port: int = typer.Option(DEFAULT_PORT, "--port", min=1, max=65535, help="Router port on 127.0.0.1."),
) -> None:
    """Start the router and every node of a launch file; Ctrl-C stops them all.

    Example: turtlectl launch --port 7448
    """
    path = file or default_launch_file()
    try:
        plan = load_launch(path)
    except LaunchFileError as exc:
        raise CliError(ExitCode.BAD_INPUT, str(exc)) from None
    printer = Printer([e.name for e in plan.launch.node])
    printer.system(f"launch file {path}")
    code = Supervisor(plan, port, printer).run()
    raise typer.Exit(code)


def _number(text: str, name: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise CliError(ExitCode.BAD_INPUT, f"{name} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise CliError(ExitCode.BAD_INPUT, f"{name} must be a finite number, got {text!r}")
    return value


@app.command(context_settings={"ignore_unknown_options": True})
def goto(
    x: str = typer.Argument(..., metavar="X", help="Goal x, m."),
    y: str = typer.Argument(..., metavar="Y", help="Goal y, m."),
    theta: str = typer.Argument(..., metavar="THETA", help="Goal heading, degrees (negative values are fine)."),
    timeout: float = typer.Option(60.0, "--timeout", min=0.1, help="Give up after this many seconds."),
    json: bool = typer.Option(False, "--json", help="Print the response as one JSON object."),
    connect: str = ConnectOption,
) -> None:
    """Send the turtle to (X, Y) facing THETA degrees and wait for the outcome.

    On a terminal a live progress line shows the goal's state; piped, only the
    outcome is printed.  Ctrl-C cancels the goal.

    Example: turtlectl goto 8 5 90
    """
    request = client.check_goal_input(_number(x, "x"), _number(y, "y"), _number(theta, "theta"))
    live = sys.stdout.isatty() and not json
    show = (lambda fb: typer.echo("\r\033[K" + format.progress_line(fb), nl=False)) if live else None
    try:
        response, _ = client.navigate(connect, request, timeout, show)
    except KeyboardInterrupt:
        raise CliError(ExitCode.INTERRUPTED, "interrupted: the navigator cancels the goal") from None
    finally:
        if live:
            typer.echo("\r\033[K", nl=False)
    typer.echo(format.message_json(response) if json else format.outcome_line(response))
    raise typer.Exit(ExitCode.OK if response.success else ExitCode.FAILED)


@app.command()
def cancel(connect: str = ConnectOption) -> None:
    """Cancel the running goal: the turtle brakes at once; its caller gets reason "canceled".

    Exit code 1 if no goal was running.

    Example: turtlectl cancel
    """
    (ack,) = client.simple_call(connect, keys.CANCEL, Cancel())
    typer.echo(ack.detail)
    raise typer.Exit(ExitCode.OK if ack.ok else ExitCode.FAILED)


@app.command(context_settings={"ignore_unknown_options": True})
def teleport(
    x: str = typer.Argument(..., metavar="X", help="x, m."),
    y: str = typer.Argument(..., metavar="Y", help="y, m."),
    theta: str = typer.Argument(..., metavar="THETA", help="Heading, degrees (as for goto)."),
    connect: str = ConnectOption,
) -> None:
    """Put the turtle at (X, Y) facing THETA degrees, at rest (turtlesim's teleport_absolute).

    Example: turtlectl teleport 2 2 45
    """
    request = TeleportAbsolute(x=_number(x, "x"), y=_number(y, "y"), theta=math.radians(_number(theta, "theta")))
    typer.echo(format.ack_lines(client.simple_call(connect, keys.TELEPORT, request)))


@app.command()
def reset(connect: str = ConnectOption) -> None:
    """Put the turtle back at its spawn pose and fill the battery (turtlesim's reset).

    Example: turtlectl reset
    """
    typer.echo(format.ack_lines(client.simple_call(connect, keys.RESET, Reset(), everyone=True)))


@app.command()
def echo(
    topic: str = typer.Argument(..., metavar="TOPIC", help="Key expression, e.g. robot/status or turtle1/*."),
    once: bool = typer.Option(False, "--once", help="Print one message and exit."),
    count: Optional[int] = typer.Option(None, "--count", min=1, help="Exit after N messages."),
    json: bool = typer.Option(False, "--json", help="One JSON object per line."),
    timeout: Optional[float] = typer.Option(None, "--timeout", min=0.0, help="Exit after S seconds."),
    connect: str = ConnectOption,
) -> None:
    """Print the messages published on TOPIC, decoded whatever their type.

    Example: turtlectl echo robot/status --count 5
    """
    limit = 1 if once else count
    printed = 0
    try:
        for item in client.stream(connect, topic, limit, timeout):
            if isinstance(item, client.Silence):
                typer.echo(f"nothing published on {topic} yet (is `turtlectl launch` running?)", err=True)
            elif item.message is None:
                typer.echo(f"skipped a message on {item.key}: {item.problem}", err=True)
            else:
                printed += 1
                typer.echo(format.message_json(item.message) if json else format.message_block(item.message))
    except KeyboardInterrupt:
        pass


def main() -> None:
    """Console entry point: run the app, turning CliError into stderr + exit code."""
    try:
        app()
    except CliError as exc:
        typer.echo(f"turtlectl: error: {exc.message}", err=True)
        sys.exit(int(exc.code))
    except KeyboardInterrupt:
        typer.echo("turtlectl: interrupted", err=True)
        sys.exit(int(ExitCode.INTERRUPTED))


if __name__ == "__main__":
    main()
