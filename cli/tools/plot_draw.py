"""How ``turtlectl plot`` draws: a chart as terminal text (plotext), a picture file (matplotlib,
Agg: no display needed), and the terminal screen a live plot is redrawn on.  Imported only by
``plot`` (plotext and matplotlib take a third of a second to import)."""

from __future__ import annotations

import contextlib
import os
import select
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TextIO

from turtlectl.runtime.client.errors import BadInput

#: s between two frames of a live plot (5 a second)
FRAME = 0.2
#: each line's color, in turn (the 256 terminal colors: blue, green, red, cyan, magenta, yellow)
COLORS = (12, 10, 9, 14, 13, 11)
#: what the time axis is called
TIME_LABEL = "time (s)"

#: a line to draw: its label, times, values
Line = tuple[str, Sequence[float], Sequence[float]]


def chart(
    lines: list[Line],
    width: int,
    height: int,
    x_limits: tuple[float, float] | None = None,
    y_limits: tuple[float, float] | None = None,
    color: bool = True,
) -> list[str]:
    """The lines as a chart of ``width`` x ``height`` terminal cells: a legend line naming each
    line in its color, then the plot (braille dots) with the time axis labelled; ``height``
    lines of text (ANSI colors with ``color``).  The legend is a line of its own so that it
    never hides a line's points (plotext draws its legend on the canvas)."""
    import plotext

    fig = plotext.figure
    fig.clear()
    plotext.terminal.limit(False, False)  # our size, not the terminal plotext finds
    fig.theme("simple")  # the terminal's own colors for the frame
    fig.plot_size(max(width, 20), max(height - 1, 5))
    for i, (_, xs, ys) in enumerate(lines):
        signal = fig.signal(list(xs), list(ys), marker=plotext.marker("braille", _color(i)))
        signal.lines()
        fig.draw(signal)
    if x_limits is not None:
        fig.ruler("x").lim(*x_limits)
    if y_limits is not None:
        fig.ruler("y").lim(*y_limits)
    fig.label(TIME_LABEL, "x")
    return [legend(lines, width, color), *fig.build().string(colorless=not color).splitlines()]


def _color(index: int) -> int:
    return COLORS[index % len(COLORS)]


def legend(lines: list[Line], width: int, color: bool = True) -> str:
    """One line naming each line after a mark in its color (``━━ robot/status.battery``), at
    most ``width`` characters shown (color codes aside): a label that does not fit is cut,
    the lines after it left out."""
    parts, shown = [], 0
    for i, (label, _, _) in enumerate(lines):
        gap = "   " if i else ""
        room = width - shown - len(gap) - 3  # "━━ " before the label
        if room < 1:
            break
        mark = f"\x1b[38;5;{_color(i)}m━━\x1b[0m" if color else "━━"
        parts.append(f"{gap}{mark} {label[:room]}")
        shown += len(gap) + 3 + len(label[:room])
    return "".join(parts)


def write_picture(path: Path, kind: str, lines: list[Line], title: str) -> None:
    """The lines as a picture at ``path`` (``kind``: png or svg): time on x, a legend naming
    each line (an SVG keeps its text as text).  BadInput (exit 2) if it cannot be written."""
    import matplotlib

    matplotlib.use("Agg")
    matplotlib.rcParams["svg.fonttype"] = "none"  # text as text: labels searchable, fonts the viewer's
    matplotlib.rcParams["svg.hashsalt"] = "turtlectl"  # the same picture for the same data
    from matplotlib.figure import Figure

    figure = Figure(figsize=(10, 5), dpi=100, layout="constrained")
    axes = figure.add_subplot()
    for label, xs, ys in lines:
        axes.plot(list(xs), list(ys), label=label, linewidth=1.2)
    axes.set_xlabel(TIME_LABEL)
    axes.set_title(title)
    axes.grid(True, alpha=0.3)
    axes.legend(loc="best")
    metadata = {"Date": None} if kind == "svg" else {}
    try:
        figure.savefig(path, format=kind, metadata=metadata)
    except OSError as exc:
        raise BadInput(f"cannot write {path}: {exc.strerror or exc}") from None


def check_writable(path: Path) -> None:
    """Before anything is collected: BadInput (exit 2) unless ``path``'s folder exists and can be
    written into, and ``path`` is no folder itself."""
    folder = path.parent
    if not folder.exists():
        raise BadInput(f"--output {str(path)!r}: no folder {folder}")
    if not folder.is_dir():
        raise BadInput(f"--output {str(path)!r}: {folder} is not a folder")
    if path.is_dir():
        raise BadInput(f"--output {str(path)!r} is a folder: name the picture file in it")
    if not os.access(folder, os.W_OK | os.X_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise BadInput(f"--output {str(path)!r}: cannot write into {folder}")


class Screen:
    """The terminal a live plot is redrawn on: the alternate screen (the shell's text comes back
    after), no cursor, keys read one by one without echo; all restored on leaving."""

    def __init__(self, out: TextIO):
        self.out = out
        self.fd_in = sys.stdin.fileno() if sys.stdin is not None and sys.stdin.isatty() else -1

    def size(self) -> tuple[int, int]:
        """(columns, rows) of the terminal now (it may have been resized)."""
        try:
            size = os.get_terminal_size(self.out.fileno())
        except (OSError, ValueError):
            return 80, 24
        return size.columns, size.lines

    def show(self, lines: list[str]) -> None:
        """Draw ``lines`` from the top left, each erasing what was right of it, and erase below."""
        self.out.write("\x1b[H" + "\n".join(line + "\x1b[K" for line in lines) + "\x1b[J")
        self.out.flush()

    def key(self, wait: float) -> str:
        """A key pressed within ``wait`` s ("" for none, or without a keyboard)."""
        if self.fd_in < 0:
            if wait > 0:
                select.select([], [], [], wait)
            return ""
        ready, _, _ = select.select([self.fd_in], [], [], wait)
        if not ready:
            return ""
        data = os.read(self.fd_in, 32)
        return data.decode(errors="replace") if data else ""


@contextlib.contextmanager
def screen(out: TextIO) -> Iterator[Screen]:
    """A Screen on ``out`` while the block runs; the terminal as it was after, whatever happens."""
    import termios
    import tty

    shown = Screen(out)
    saved = None
    if shown.fd_in >= 0:
        saved = termios.tcgetattr(shown.fd_in)
        tty.setcbreak(shown.fd_in)
    out.write("\x1b[?1049h\x1b[?25l\x1b[H\x1b[2J")
    out.flush()
    try:
        yield shown
    finally:
        out.write("\r\n\x1b[?25h\x1b[?1049l")  # the last line ended (a terminal without the alternate screen)
        out.flush()
        if saved is not None:
            termios.tcsetattr(shown.fd_in, termios.TCSADRAIN, saved)
