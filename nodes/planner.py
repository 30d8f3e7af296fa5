"""The global planner as pure functions: the shortest way around circles, no I/O, no zenoh.

The turtle is a point that must keep out of circles (each obstacle inflated by the
turtle's size and a margin) and inside the square world [0, size]^2.  The shortest
such path is made of straight segments tangent to the circles and arcs along them
(a visibility graph of tangents: from the start and the goal to every circle, four
between every pair of circles, and the arcs that join tangent points on a circle);
Dijkstra's algorithm finds the shortest way through it.  The path is exact: no grid,
and it turns only where it follows a circle (its heading is continuous between
pieces), so a follower can drive it without stopping.

Units: m, rad (angles counter-clockwise from +x).
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from turtlectl.messages.world import Obstacle

#: m: how far a tangent may dip into a circle (rounding), and how close counts as on a circle
EPS = 1e-7
TWO_PI = 2.0 * math.pi


class Circle(NamedTuple):
    """A disk the path must keep out of: centre (x, y) and radius r, m."""

    x: float
    y: float
    r: float


@dataclass(frozen=True)
class Segment:
    """A straight piece from (ax, ay) to (bx, by), m."""

    ax: float
    ay: float
    bx: float
    by: float

    @property
    def length(self) -> float:
        return math.hypot(self.bx - self.ax, self.by - self.ay)

    def point(self, s: float) -> tuple[float, float]:
        """The point ``s`` m from the start (0 <= s <= length)."""
        t = s / self.length if self.length > 0.0 else 0.0
        return self.ax + t * (self.bx - self.ax), self.ay + t * (self.by - self.ay)

    def heading(self, s: float = 0.0) -> float:
        """Direction of travel (rad); the same all along."""
        return math.atan2(self.by - self.ay, self.bx - self.ax)


@dataclass(frozen=True)
class Arc:
    """A piece along the circle of centre (cx, cy) and radius r (m), from angle ``start``
    (rad, where on the circle) turning ``sweep`` rad (> 0 counter-clockwise, < 0 clockwise)."""

    cx: float
    cy: float
    r: float
    start: float
    sweep: float

    @property
    def length(self) -> float:
        return self.r * abs(self.sweep)

    def point(self, s: float) -> tuple[float, float]:
        """The point ``s`` m from the start (0 <= s <= length)."""
        a = self.start + math.copysign(s / self.r, self.sweep)
        return self.cx + self.r * math.cos(a), self.cy + self.r * math.sin(a)

    def heading(self, s: float = 0.0) -> float:
        """Direction of travel (rad) ``s`` m from the start: the tangent of the circle."""
        a = self.start + math.copysign(s / self.r, self.sweep)
        return a + math.copysign(math.pi / 2, self.sweep)


Piece = Segment | Arc


@dataclass(frozen=True)
class Path:
    """A way from a start to a goal: segments and arcs, each beginning where the last ends."""

    pieces: tuple[Piece, ...]

    @property
    def length(self) -> float:
        """Total length, m."""
        return sum(p.length for p in self.pieces)

    @property
    def start(self) -> tuple[float, float]:
        return self.pieces[0].point(0.0)

    @property
    def end(self) -> tuple[float, float]:
        last = self.pieces[-1]
        return last.point(last.length)

    @property
    def direct(self) -> bool:
        """One straight segment: nothing is in the way."""
        return len(self.pieces) == 1 and isinstance(self.pieces[0], Segment)

    def final_segment_start(self) -> float:
        """Where (m from the start) the last straight run to the goal begins; the length if
        the path ends on an arc."""
        last = self.pieces[-1]
        return self.length - (last.length if isinstance(last, Segment) else 0.0)

    def points(self, spacing: float) -> np.ndarray:
        """Points along the path, shape (n, 2), m: every piece's ends, and points at most
        ``spacing`` m apart in between."""
        out = [self.start]
        for piece in self.pieces:
            n = max(1, math.ceil(piece.length / spacing))
            out.extend(piece.point(piece.length * i / n) for i in range(1, n + 1))
        return np.asarray(out, dtype=float)

    def outline(self, max_turn: float = math.radians(10.0)) -> list[tuple[float, float]]:
        """Few points that draw the path (m): segments by their ends, arcs a point every
        ``max_turn`` rad at most."""
        out = [self.start]
        for piece in self.pieces:
            n = 1 if isinstance(piece, Segment) else max(1, math.ceil(abs(piece.sweep) / max_turn))
            out.extend(piece.point(piece.length * i / n) for i in range(1, n + 1))
        return out


def inflate(obstacles: Iterable[Obstacle], by: float) -> list[Circle]:
    """The obstacles as circles grown by ``by`` m (the turtle's size and a margin)."""
    return [Circle(o.x, o.y, o.radius + by) for o in obstacles]


def containing(x: float, y: float, circles: Sequence[Circle]) -> Circle | None:
    """The first circle that (x, y) lies inside (its boundary excluded), or None."""
    for c in circles:
        if math.hypot(x - c.x, y - c.y) < c.r - EPS:
            return c
    return None


def escape(x: float, y: float, circles: Sequence[Circle]) -> list[Circle]:
    """The circles, each shrunk so that (x, y) is not inside it: a turtle that stands within
    an obstacle's margin (teleported there, or the margin grew) may still leave it."""
    out = []
    for c in circles:
        d = math.hypot(x - c.x, y - c.y)
        out.append(Circle(c.x, c.y, min(c.r, d - 2 * EPS)) if d < c.r else c)
    return [c for c in out if c.r > 0.0]


def wall_plugs(circles: Sequence[Circle], size: float, gap: float) -> list[Circle]:
    """Circles (m) that close each passage narrower than ``gap`` m between one of ``circles``
    and a wall of the world [0, size]^2: a turtle of radius ``gap`` cannot pass there without
    its body going through the wall.  Each is centred on the wall at the foot of the circle,
    reaching a little into it."""
    plugs = []
    for c in circles:
        for away, x, y in ((c.x, 0.0, c.y), (size - c.x, size, c.y), (c.y, c.x, 0.0), (size - c.y, c.x, size)):
            if 0.0 < away - c.r < gap:
                plugs.append(Circle(x, y, away - c.r + min(0.02, c.r)))
    return plugs


def _angle_in(a: float, start: float, sweep: float) -> bool:
    """``a`` lies strictly inside the counter-clockwise range from ``start`` over ``sweep`` (>= 0)."""
    d = (a - start) % TWO_PI
    return EPS < d < sweep - EPS


def _segment_clear(
    ax: float, ay: float, bx: float, by: float, circles: Sequence[Circle], skip: tuple[int, ...]
) -> bool:
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    for k, c in enumerate(circles):
        if k in skip:
            continue
        t = 0.0 if length2 == 0.0 else max(0.0, min(1.0, ((c.x - ax) * dx + (c.y - ay) * dy) / length2))
        if math.hypot(ax + t * dx - c.x, ay + t * dy - c.y) < c.r - EPS:
            return False
    return True


def _point_free(x: float, y: float, size: float, circles: Sequence[Circle], skip: int) -> bool:
    if not (-EPS <= x <= size + EPS and -EPS <= y <= size + EPS):
        return False
    return all(k == skip or math.hypot(x - c.x, y - c.y) >= c.r - EPS for k, c in enumerate(circles))


def _arc_clear(i: int, start: float, sweep: float, circles: Sequence[Circle], size: float) -> bool:
    """The counter-clockwise arc of circle ``i`` from ``start`` over ``sweep`` rad stays inside
    the world and out of every other circle (its ends are known to)."""
    c = circles[i]
    for a, limit_ok in (
        (0.0, c.x + c.r <= size + EPS),
        (math.pi / 2, c.y + c.r <= size + EPS),
        (math.pi, c.x - c.r >= -EPS),
        (3 * math.pi / 2, c.y - c.r >= -EPS),
    ):
        if not limit_ok and _angle_in(a, start, sweep):
            return False
    for k, o in enumerate(circles):
        if k == i:
            continue
        d = math.hypot(o.x - c.x, o.y - c.y)
        if d >= c.r + o.r or d <= abs(c.r - o.r):
            continue  # apart, or one inside the other: the ends' checks decide
        # where the two circles cross, seen from c's centre
        base = math.atan2(o.y - c.y, o.x - c.x)
        half = math.acos(max(-1.0, min(1.0, (c.r * c.r + d * d - o.r * o.r) / (2 * c.r * d))))
        if _angle_in(base + half, start, sweep) or _angle_in(base - half, start, sweep):
            return False
        # an arc that ends on o's boundary and runs inside it
        mid = start + 0.5 * sweep
        if math.hypot(c.x + c.r * math.cos(mid) - o.x, c.y + c.r * math.sin(mid) - o.y) < o.r - EPS:
            return False
    return True


def _point_tangents(px: float, py: float, c: Circle) -> list[float]:
    """Angles on ``c`` of the two tangents from (px, py), which lies outside it."""
    d = math.hypot(px - c.x, py - c.y)
    if d < c.r:
        return []
    base = math.atan2(py - c.y, px - c.x)
    half = math.acos(min(1.0, c.r / d)) if d > 0.0 else 0.0
    return [base + half, base - half]


def _bitangents(a: Circle, b: Circle) -> list[tuple[float, float]]:
    """Angles (on a, on b) of the tangent points of the lines tangent to both circles:
    the two outer ones, and the two inner ones when the circles are apart."""
    d = math.hypot(b.x - a.x, b.y - a.y)
    base = math.atan2(b.y - a.y, b.x - a.x)
    out = []
    if d > abs(a.r - b.r):
        half = math.acos((a.r - b.r) / d)
        out += [(base + half, base + half), (base - half, base - half)]
    if d > a.r + b.r:
        half = math.acos((a.r + b.r) / d)
        out += [(base + half, base + half + math.pi), (base - half, base - half + math.pi)]
    return out


def shortest_path(
    start: tuple[float, float], goal: tuple[float, float], circles: Sequence[Circle], size: float
) -> Path | None:
    """The shortest path (m) from ``start`` to ``goal`` that stays inside [0, size]^2 and
    out of every circle, or None if there is none (the goal is enclosed or inside one).

    The start must not lie inside a circle (``escape`` makes it so); the path's pieces
    are tangent to one another.
    """
    circles = list(circles)
    if containing(*goal, circles) is not None or containing(*start, circles) is not None:
        return None
    # nodes: 0 start, 1 goal, then tangent points (x, y, circle, angle)
    xs, ys = [start[0], goal[0]], [start[1], goal[1]]
    on: list[tuple[int, float]] = [(-1, 0.0), (-1, 0.0)]
    edges: list[list[tuple[int, float, Piece]]] = [[], []]
    on_circle: list[list[int]] = [[] for _ in circles]

    def node(i: int, angle: float) -> int:
        c = circles[i]
        xs.append(c.x + c.r * math.cos(angle))
        ys.append(c.y + c.r * math.sin(angle))
        on.append((i, angle % TWO_PI))
        edges.append([])
        on_circle[i].append(len(xs) - 1)
        return len(xs) - 1

    def link(u: int, v: int, piece_uv: Piece, piece_vu: Piece) -> None:
        edges[u].append((v, piece_uv.length, piece_uv))
        edges[v].append((u, piece_vu.length, piece_vu))

    def segment_link(u: int, v: int) -> None:
        link(u, v, Segment(xs[u], ys[u], xs[v], ys[v]), Segment(xs[v], ys[v], xs[u], ys[u]))

    if _segment_clear(*start, *goal, circles, ()):
        segment_link(0, 1)
    for end in (0, 1):
        for i, c in enumerate(circles):
            for angle in _point_tangents(xs[end], ys[end], c):
                tx, ty = c.x + c.r * math.cos(angle), c.y + c.r * math.sin(angle)
                if _point_free(tx, ty, size, circles, i) and _segment_clear(xs[end], ys[end], tx, ty, circles, (i,)):
                    segment_link(end, node(i, angle))
    for i, a in enumerate(circles):
        for j in range(i + 1, len(circles)):
            b = circles[j]
            for ta, tb in _bitangents(a, b):
                ax, ay = a.x + a.r * math.cos(ta), a.y + a.r * math.sin(ta)
                bx, by = b.x + b.r * math.cos(tb), b.y + b.r * math.sin(tb)
                if (
                    _point_free(ax, ay, size, circles, i)
                    and _point_free(bx, by, size, circles, j)
                    and _segment_clear(ax, ay, bx, by, circles, (i, j))
                ):
                    segment_link(node(i, ta), node(j, tb))
    for i, members in enumerate(on_circle):
        if len(members) < 2:
            continue
        c = circles[i]
        members.sort(key=lambda n: on[n][1])
        for u, v in zip(members, members[1:] + members[:1], strict=True):
            start_angle = on[u][1]
            sweep = (on[v][1] - start_angle) % TWO_PI
            if _arc_clear(i, start_angle, sweep, circles, size):
                link(u, v, Arc(c.x, c.y, c.r, start_angle, sweep), Arc(c.x, c.y, c.r, on[v][1], -sweep))

    best = [math.inf] * len(xs)
    came: list[tuple[int, Piece] | None] = [None] * len(xs)
    best[0] = 0.0
    heap = [(0.0, 0)]
    while heap:
        d, u = heapq.heappop(heap)
        if d > best[u]:
            continue
        if u == 1:
            break
        for v, w, piece in edges[u]:
            if d + w < best[v]:
                best[v], came[v] = d + w, (u, piece)
                heapq.heappush(heap, (d + w, v))
    if math.isinf(best[1]):
        return None
    pieces: list[Piece] = []
    at = 1
    while (step := came[at]) is not None:
        at, piece = step
        if piece.length > EPS:
            pieces.append(piece)
    if not pieces:
        pieces = [Segment(*start, *goal)]
    return Path(tuple(reversed(pieces)))


class Track:
    """A path as points a few cm apart, for a follower: where along it the turtle is, and
    the point some way ahead.  ``s`` (m) is the distance along the path of each point."""

    def __init__(self, path: Path, spacing: float = 0.02):
        self.path = path
        xy, radius = [path.start], [math.inf]
        for piece in path.pieces:
            n = max(1, math.ceil(piece.length / spacing))
            xy.extend(piece.point(piece.length * i / n) for i in range(1, n + 1))
            radius.extend([piece.r if isinstance(piece, Arc) else math.inf] * n)
        self.xy = np.asarray(xy, dtype=float)
        self.radius = np.asarray(radius)  # m: of the arc each point lies on (inf: on a segment)
        steps = np.hypot(*np.diff(self.xy, axis=0).T)
        self.s = np.concatenate(([0.0], np.cumsum(steps)))
        self.length = float(self.s[-1])
        self.final_start = path.final_segment_start()

    def project(self, x: float, y: float, hint: int = 0, behind: int = 25, ahead: int = 250) -> int:
        """Index of the point nearest (x, y) among those from ``behind`` points before
        ``hint`` (the last answer) to ``ahead`` after it: progress never jumps to a far
        part of a path that comes back near itself."""
        lo, hi = max(0, hint - behind), min(len(self.s), hint + ahead + 1)
        window = self.xy[lo:hi]
        return lo + int(np.argmin(np.hypot(window[:, 0] - x, window[:, 1] - y)))

    def tightest(self, start: int, end: float) -> float:
        """The smallest radius (m) of the arcs from point ``start`` to ``end`` m along; inf if straight."""
        stop = int(np.searchsorted(self.s, end)) + 1
        return float(self.radius[start:stop].min()) if stop > start else math.inf

    def point_at(self, s: float) -> tuple[float, float]:
        """The point (m) ``s`` m along the track (clamped to its ends)."""
        i = min(len(self.s) - 1, int(np.searchsorted(self.s, s)))
        return float(self.xy[i, 0]), float(self.xy[i, 1])

    def blocked_by(self, circles: Sequence[Circle], since: int = 0) -> Circle | None:
        """The first circle that the track, from point ``since`` on, enters; None if clear."""
        rest = self.xy[since:]
        for c in circles:
            if np.any(np.hypot(rest[:, 0] - c.x, rest[:, 1] - c.y) < c.r - EPS):
                return c
        return None
