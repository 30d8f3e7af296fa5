"""turtlectl's plot command: fields of messages drawn over time, live in the terminal (as
`rqt_plot`), from a recording, or into a picture.

The model (cli.tools.plot), the sources (cli.tools.plot_sources) and the drawing
(cli.tools.plot_draw: plotext and matplotlib) are imported inside the command."""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import typer

from turtlectl.cli import args
from turtlectl.cli.commands.options import ConnectOption, DomainOption, ExitOnLossOption, TurtleOption, result
from turtlectl.runtime.client.errors import BadInput, Unreachable


def plot(
    fields: list[str] = typer.Argument(
        ...,
        metavar="KEY.FIELD...",
        help="What to plot: a key, a '.', a numeric field (robot/status.battery, turtle1/pose.x, obstacles.ranges.0).",
    ),
    recording: Path | None = typer.Option(
        None, "-i", "--input", metavar="FILE", help="Plot a recording (MCAP file) whole, instead of a running system."
    ),
    output: Path | None = typer.Option(
        None,
        "-o",
        "--output",
        metavar="FILE",
        help="Write a picture (.png or .svg) instead of drawing in the terminal.",
    ),
    window: float = typer.Option(10.0, "--window", min=1.0, help="Seconds the live plot shows (a sliding window)."),
    duration: float | None = typer.Option(None, "--duration", min=0.1, help="Stop after S seconds (a running system)."),
    stamps: bool = typer.Option(
        False,
        "--stamps",
        help="Time axis: each message's own stamp (simulated time with launch --time-scale), not when it arrived.",
    ),
    exit_on_loss: bool = ExitOnLossOption,
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Plot numeric fields over time, one line each, as `rqt_plot`: live in this terminal from a
    running system (the last --window seconds, redrawn 5 times a second), or a recording whole
    (--input), or into a picture (--output FILE.png or .svg).

    KEY.FIELD is a key, then a '.' and the field (nested fields and list items as echo's
    --field: navigate_to/feedback.path.0.1); with --turtle turtle2, the key as turtle2's nodes
    write it.  A bool plots as 0 or 1; inf and NaN are left out.  A field that is not a number
    is exit code 2, naming the numeric fields of its type.  The live plot runs until q or Ctrl-C
    (exit code 0) or --duration; with --output, a running system's messages are collected until
    --duration or Ctrl-C, then drawn.  No number to plot at all is exit code 3.  A lost router
    is said (on the bottom line, or on stderr with --output) and waited for; --exit-on-loss
    exits with code 3 instead.  The time axis
    is when each message arrived (a recording's: when it was recorded); --stamps: each
    message's own stamp, for a system on simulated time (launch --time-scale).

    Example: turtlectl plot robot/status.battery turtle1/pose.x
    """
    from turtlectl.cli.tools import plot as model
    from turtlectl.messages.keys import turtle_namespace
    from turtlectl.runtime.client.session import turtle_namespace_at

    # the namespace of --turtle's nodes: the running system's; a recording's, turtle1's outside any
    turtle = turtle_namespace_at(connect, turtle, domain) if recording is None else turtle_namespace(turtle)
    series = model.parse_all(fields, turtle)
    args.finite_option(window, "--window")
    args.finite_option(duration, "--duration")
    kind = ""
    if output is not None:
        from turtlectl.cli.tools.plot_draw import check_writable

        kind = model.picture_format(output)
        check_writable(output)  # before collecting: nothing is lost to a folder that is not there
    if recording is not None:
        if duration is not None:
            raise BadInput("--duration is for a running system: a recording (--input) is plotted whole")
        _plot_recording(series, recording, output, kind, stamps)
        return
    model.check_builtins(series, turtle, stamps)  # a built-in key's type is known: a typo is said at once
    if output is not None:
        _collect_live(series, output, kind, duration, connect, domain, stamps, turtle, exit_on_loss)
    else:
        if not sys.stdout.isatty():
            raise BadInput(
                "the live plot draws in a terminal, and the output is not one: write a picture with "
                "--output FILE.png (with --duration S), or the numbers with `turtlectl echo KEY --field FIELD --csv`"
            )
        plot_live(series, window, duration, connect, domain, stamps, turtle, exit_on_loss)


def _lines(series: list[Any], points: Any) -> list[Any]:
    return [(s.label, *points.xy(s)) for s in series]


def _plot_recording(series: list[Any], path: Path, output: Path | None, kind: str, stamps: bool = False) -> None:
    """A recording whole: a picture, or one chart printed in the terminal."""
    import shutil

    from turtlectl.cli.tools import plot_draw, plot_sources

    got = plot_sources.from_recording(path, series, stamps)
    if not got.closed:
        from turtlectl.cli.recording.recover import hint

        typer.echo(
            f"warning: {path} was not closed (the recorder was killed?): plotting what is complete; {hint(path)}",
            err=True,
        )
    for s in got.collected.empty():
        typer.echo(f"warning: no number in {s.label} (only inf or NaN)", err=True)
    lines = _lines(series, got.collected)
    if output is not None:
        plot_draw.write_picture(output, kind, lines, path.name)
        result(wrote(output, got.collected, got.duration))
        return
    cols, rows = shutil.get_terminal_size((100, 30))
    x_limits = (0.0, max(got.duration, 1e-3))
    text = plot_draw.chart(lines, cols, max(rows - 2, 8), x_limits, None, color=sys.stdout.isatty())
    result("\n".join(text) + f"\n{path.name}: {_samples(got.collected.count)} over {got.duration:.1f} s")


def _samples(count: int) -> str:
    return f"{count} sample{'s' * (count != 1)}"


def wrote(output: Path, collected: Any, seconds: float) -> str:
    count = len(collected.series)
    return f"wrote {output}: {_samples(collected.count)} of {count} series over {seconds:.1f} s"


@contextlib.contextmanager
def _live(
    series: list[Any],
    connect: str,
    domain: str,
    stamps: bool,
    turtle: str,
    intro: str = "",
    signals: tuple[Any, ...] = (),
    exit_on_loss: bool = False,
) -> Iterator[tuple[Any, threading.Event]]:
    """A running system's numbers (plot_sources.Live, closed after the block) and the event
    Ctrl-C, SIGTERM and ``signals`` set; ``intro`` (if any) and the typo notes said first."""
    from turtlectl.cli.tools import plot_sources
    from turtlectl.runtime.client import session as client
    from turtlectl.runtime.client.sigint import stop_on_signals

    with client.client_session(connect, domain) as session, stop_on_signals(signals) as stop:
        live = plot_sources.Live(session, connect, series, stamps, turtle, exit_on_loss)
        try:
            if intro:
                typer.echo(intro, err=True)
            for note in live.typos.values():  # a typo said at once (the key is still waited for, as echo does)
                typer.echo(f"note: {note}", err=True)
            yield live, stop
        finally:
            live.close()


def _nothing(live: Any, within: str) -> Unreachable:
    """No message within ``within`` s at all, and why the keys are silent."""
    return Unreachable(f"no message within {within} s: {live.why_silent()}")


def _collect_live(
    series: list[Any],
    output: Path,
    kind: str,
    duration: float | None,
    connect: str,
    domain: str,
    stamps: bool,
    turtle: str,
    exit_on_loss: bool = False,
) -> None:
    """A running system's numbers until --duration or Ctrl-C, then a picture of them."""
    from turtlectl.cli.tools import plot_draw
    from turtlectl.cli.tools.plot_window import Collected

    collected = Collected(series)
    told: set[str] = set()
    ends = f"for {duration:g} s" if duration is not None else "until Ctrl-C"
    labels = ", ".join(s.label for s in series)
    intro = f"plotting {labels} into {output} {ends}"
    with _live(series, connect, domain, stamps, turtle, intro, exit_on_loss=exit_on_loss) as (live, stop):
        while not stop.is_set() and (duration is None or live.elapsed() < duration):
            wait = 0.1 if duration is None else max(0.0, min(0.1, duration - live.elapsed()))
            for s, t, value in live.poll(wait):
                collected.add(s, t, value)
            for line in live.said:  # the router lost, back
                typer.echo(line, err=True)
            live.said.clear()
            for notice in live.notices:
                if notice not in told:
                    told.add(notice)
                    typer.echo(notice, err=True)
        seconds = live.elapsed()
        if not collected.count:
            raise _nothing(live, f"{seconds:.1f}")
    for s in collected.empty():
        typer.echo(f"warning: no number in {s.label} within {seconds:.1f} s", err=True)
    if stamps:
        seconds = collected.rebase()  # the stamps' span
    plot_draw.write_picture(output, kind, _lines(series, collected), "turtlectl plot")
    result(wrote(output, collected, seconds))


def plot_live(
    series: list[Any],
    window: float,
    duration: float | None,
    connect: str,
    domain: str,
    stamps: bool = False,
    turtle: str = "",
    exit_on_loss: bool = False,
) -> None:
    """The live plot in this terminal, redrawn every FRAME s, until q, Ctrl-C or --duration;
    ended by --duration, its last frame is printed (the bottom line without "q quits")."""
    from turtlectl.cli.tools import plot_draw
    from turtlectl.cli.tools.plot_window import Window, status_line

    shown = Window(series, window)
    chart: list[str] = []
    last = ""
    timed_out = False  # ended by --duration: its last frame stays in the terminal
    try:
        with _live(series, connect, domain, stamps, turtle, signals=(signal.SIGHUP,), exit_on_loss=exit_on_loss) as (
            live,
            stop,
        ):
            with plot_draw.screen(sys.stdout) as screen:  # the notes are on the terminal after the plot
                while not stop.is_set():
                    for s, t, value in live.poll():
                        shown.add(s, t, value)
                    live.said.clear()  # the bottom line says the router is lost while it is
                    shown.advance(shown.now if stamps else live.elapsed())  # stamps: the latest
                    cols, rows = screen.size()
                    if cols < 30 or rows < 8:
                        chart = ["terminal too small"]
                        screen.show(chart)
                    else:
                        lines = _lines(series, shown)
                        chart = plot_draw.chart(lines, cols, rows - 1, shown.x_limits(), shown.y_limits())
                        screen.show([*chart, status_line(shown, cols, live.silent, live.router)])
                    timed_out = duration is not None and live.elapsed() >= duration
                    if timed_out or screen.key(plot_draw.FRAME).lower().startswith("q"):
                        break
            if timed_out:  # the last frame, its bottom line ended, before any error
                cols = plot_draw.Screen(sys.stdout).size()[0]
                bottom = status_line(shown, max(cols, 30), live.silent, live.router, quits=False)
                last = "\n".join([*chart, bottom])
                if not live.received:
                    typer.echo(last)
                    raise _nothing(live, f"{duration:g}")
    except KeyboardInterrupt:  # before the screen was up: as echo, Ctrl-C ends it
        return
    if timed_out:
        result(last)


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.command()(plot)
