"""``turtlectl plot``'s samples (pure: no Zenoh, no terminal, no files, nothing printed):

- ``Window``: each series' samples over the last ``seconds`` (the live terminal plot), and the
  axes' limits to draw them with (``x_limits``, ``y_limits``); ``status_line``, the live plot's
  bottom line (each series' latest number, or why its key is silent).
- ``Collected``: every sample of each series (a recording's, or a live run's for ``--output``).
"""

from __future__ import annotations

import collections
import dataclasses
from collections.abc import Collection

from turtlectl.cli.tools.plot import Series


class Window:
    """The samples of each series over the last ``seconds`` s (a live plot's sliding window),
    times in s since the plot started; one sample older than the window is kept so a line
    comes in from the left edge."""

    def __init__(self, series: list[Series], seconds: float):
        self.seconds = seconds
        self.points: dict[Series, collections.deque[tuple[float, float]]] = {s: collections.deque() for s in series}
        self.latest: dict[Series, float] = {}
        self.now = 0.0

    def add(self, series: Series, t: float, value: float) -> None:
        self.points[series].append((t, value))
        self.latest[series] = value
        self.now = max(self.now, t)

    def advance(self, now: float) -> None:
        """The time is ``now``: samples that left the window (but the last before it) go."""
        self.now = max(self.now, now)
        start = self.now - self.seconds
        for points in self.points.values():
            while len(points) > 1 and points[1][0] <= start:
                points.popleft()

    def x_limits(self) -> tuple[float, float]:
        """The time axis: [0, seconds] until the window is full, then the last ``seconds`` s."""
        return (max(0.0, self.now - self.seconds), max(self.seconds, self.now))

    def y_limits(self) -> tuple[float, float] | None:
        """Room for every sample in the window (5 % more each side); None while there is none."""
        lo, hi = self.x_limits()
        values = [v for points in self.points.values() for t, v in points if lo <= t <= hi]
        return value_limits(values)

    def xy(self, series: Series) -> tuple[list[float], list[float]]:
        """The times and values of one series."""
        return _xy(self.points[series])


def _xy(points: Collection[tuple[float, float]]) -> tuple[list[float], list[float]]:
    """The times and the values of ``points`` (time, value)."""
    return [t for t, _ in points], [v for _, v in points]


def short_reason(key: str, why: str) -> str:
    """A silent key's reason (as echo says it: ``nothing published on KEY yet: no running node
    publishes it (...)``) short enough for its slot of the status line: ``no running node publishes it``."""
    said = why.partition(f"nothing published on {key} ")[2] or why
    for lead in ("yet: ", "here: "):
        said = said.removeprefix(lead)
    return said.split(" (")[0].split(": it may")[0]


def status_line(
    window: Window, width: int, silent: dict[str, str] | None = None, router: str = "", quits: bool = True
) -> str:
    """The live plot's bottom line, at most ``width - 1`` characters: each series in its slot,
    its latest number or that it waits for one, with a short reason while its key is
    ``silent`` (key -> why); the router lost (``router``) first; then how to quit (``quits``)."""
    silent = silent or {}
    slots = []
    for s in window.points:
        value = f" {window.latest[s]:.6g}" if s in window.latest else ""
        if s.key in silent:
            reason = short_reason(s.key, silent[s.key])
            slots.append(f"{s.label}{value} (silent{' ' if reason.startswith('for ') else ': '}{reason})")
        else:
            slots.append(f"{s.label}{value or ' (waiting)'}")
    said = "  ".join(slots)
    if router:
        said = f"{router.split(' (')[0]} | {said}"
    if quits:
        said += " | q quits"
    return said[: max(0, width - 1)]


def value_limits(values: list[float]) -> tuple[float, float] | None:
    """A value axis for ``values``: 5 % of their span more each side, ±1 around a constant
    (a line held at 100 % shows as a line, not on the frame); None for no values."""
    if not values:
        return None
    lo, hi = min(values), max(values)
    if hi - lo < 1e-9 * max(1.0, abs(hi)):
        return (lo - 1.0, hi + 1.0)
    margin = (hi - lo) * 0.05
    return (lo - margin, hi + margin)


@dataclasses.dataclass
class Collected:
    """Every sample of each series (a recording's, or a live run's for ``--output``): times in s
    from ``origin`` (the recording's start, or when the plot started)."""

    series: list[Series]
    points: dict[Series, list[tuple[float, float]]] = dataclasses.field(default_factory=dict)

    def __post_init__(self) -> None:
        for s in self.series:
            self.points.setdefault(s, [])

    def add(self, series: Series, t: float, value: float) -> None:
        self.points[series].append((t, value))

    @property
    def count(self) -> int:
        return sum(len(p) for p in self.points.values())

    def empty(self) -> list[Series]:
        """The series without a sample."""
        return [s for s in self.series if not self.points[s]]

    def xy(self, series: Series) -> tuple[list[float], list[float]]:
        """The times and values of one series."""
        return _xy(self.points[series])

    def rebase(self) -> float:
        """Times from the earliest sample (0 from then on); the span, s."""
        times = [t for points in self.points.values() for t, _ in points]
        first = min(times, default=0.0)
        for s, points in self.points.items():
            self.points[s] = [(t - first, v) for t, v in points]
        return max(times) - first if times else 0.0

    def span(self) -> float:
        """Seconds from the first sample to the last, of any series."""
        times = [t for points in self.points.values() for t, _ in points]
        return max(times) - min(times) if times else 0.0
