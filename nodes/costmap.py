"""What the scans have seen that the world does not declare, remembered in world
coordinates: a small occupancy grid, as Nav2's obstacle layer.  Pure numpy: no I/O, no
clock, no zenoh.

A cell is marked by scan hits that no declared obstacle explains and cleared by beams that
pass through it, so a phantom (or anything that goes away) is forgotten once the turtle
looks through where it was, while the far side of a thing, which no beam reaches, stays
known after the turtle has driven round it.  The marked cells are handed to the planner
as a bounded number of circles.

Units: m; angles rad (beam angles in the scanner's frame, 0 = straight ahead, CCW positive).
"""

from __future__ import annotations

import math

import numpy as np

from turtlectl.nodes.planner import Circle

#: m a circle reaches beyond the hits it covers: room for the surface between hits, and for
#: what a sparse or late scan shows of it (0.02 let a turtle circling a ring of such things
#: come to 0.23 m of one, tests/unit/nodes/test_goal_machine.py)
PAD = 0.07
#: m a single hit's circle reaches beyond it (near a goal, where the turtle drives slowly)
HIT_PAD = 0.02


class Costmap:
    """Cells of ``resolution`` m over the square world [0, size]^2; ``grid`` is True where
    something is (False: free, or never seen), and ``hits`` holds, for each such cell, the
    latest hit (m) that marked it: where the thing was seen, not the cell's centre (a cell
    alone would place a surface up to a cell nearer than it is)."""

    def __init__(self, size: float, resolution: float = 0.1):
        self.size = size
        self.resolution = resolution
        self.cells = max(1, math.ceil(size / resolution))
        self.grid = np.zeros((self.cells, self.cells), dtype=bool)  # [ix, iy]
        self.hits = np.zeros((self.cells, self.cells, 2))  # [ix, iy] -> (x, y), where grid is True
        centres = (np.arange(self.cells) + 0.5) * resolution
        self._cx, self._cy = np.meshgrid(centres, centres, indexing="ij")

    def update(
        self,
        x: float,
        y: float,
        theta: float,
        ranges: np.ndarray,
        angle_min: float,
        angle_increment: float,
        range_max: float,
        unknown: np.ndarray,
    ) -> None:
        """One scan taken at (x, y, theta): each beam (``ranges`` m, ``inf`` = nothing within
        ``range_max``) clears the cells it passes through short of its hit (a cell short of
        it), then each of ``unknown`` (hits, world coordinates (n, 2), that no declared
        obstacle explains) marks its cell."""
        r = np.asarray(ranges, dtype=float)
        n = len(r)
        if n and math.isfinite(angle_min) and math.isfinite(angle_increment):
            reach = np.where(np.isfinite(r), r, range_max) - self.resolution
            dx, dy = self._cx - x, self._cy - y
            distance = np.hypot(dx, dy)
            step = angle_increment if angle_increment != 0.0 else 2.0 * math.pi
            bearing = np.mod(np.arctan2(dy, dx) - theta - angle_min + 0.5 * step, 2.0 * math.pi) - 0.5 * step
            beam = np.rint(bearing / step).astype(int)
            if math.isclose(abs(step) * n, 2.0 * math.pi, rel_tol=1e-6):  # a full turn: the last beam meets the first
                beam %= n
            seen = (beam >= 0) & (beam < n)
            free = seen & (distance < reach[np.clip(beam, 0, n - 1)])
            self.grid[free] = False
        p = np.asarray(unknown, dtype=float).reshape(-1, 2)
        if len(p):
            ix = np.clip((p[:, 0] / self.resolution).astype(int), 0, self.cells - 1)
            iy = np.clip((p[:, 1] / self.resolution).astype(int), 0, self.cells - 1)
            self.grid[ix, iy] = True
            self.hits[ix, iy] = p

    def occupied(self) -> np.ndarray:
        """The hits (m), shape (n, 2), of the cells where something is."""
        return self.hits[self.grid]

    def within(self, x: float, y: float, r: float) -> np.ndarray:
        """The hits (m), shape (n, 2), within ``r`` m of (x, y)."""
        p = self.occupied()
        return p[np.hypot(p[:, 0] - x, p[:, 1] - y) <= r + 1e-9]

    def nearest(self, x: float, y: float) -> tuple[float, tuple[float, float] | None]:
        """The distance (m) from (x, y) to the nearest thing seen, and where that is (inf and
        None if nothing is)."""
        p = self.occupied()
        if not len(p):
            return math.inf, None
        d = np.hypot(p[:, 0] - x, p[:, 1] - y)
        k = int(np.argmin(d))
        return float(d[k]), (float(p[k, 0]), float(p[k, 1]))

    def circles(self, piece: float = 0.5, most: int = 24) -> list[Circle]:
        """The marked cells as circles (m) that cover the hits of every one of them: the cells in
        each square of side ``piece`` of the world, one circle for each group of them that
        touch (larger squares if that would give more than ``most`` circles: the planner's
        cost grows with the cube of their number; past one square over the whole world,
        the nearest circles merged).  Small squares keep a circle from
        bulging far over free space (the hollow of a ring, the inside of a bend)."""
        ix, iy = np.nonzero(self.grid)
        if not len(ix):
            return []
        xy = self.hits[ix, iy]
        side = piece
        while True:
            tiles = np.floor(xy / side).astype(int)
            _, which = np.unique(tiles, axis=0, return_inverse=True)
            which = which.ravel()
            circles = []
            for k in range(int(which.max()) + 1):
                members = np.flatnonzero(which == k)
                for group in _touching(ix[members], iy[members]):
                    circles.append(_cover(xy[members[group]]))
            if len(circles) <= most or side > self.size:  # one square over the world: growing it changes nothing
                return _merge(circles, most)
            side *= 1.5


def _merge(circles: list[Circle], most: int) -> list[Circle]:
    """``circles`` (m), the two whose joint cover is smallest merged until at most ``most``
    are left (things seen apart, more of them than ``most``, that no square joins)."""
    circles = list(circles)
    while len(circles) > max(1, most):
        best = None
        for i, a in enumerate(circles):
            for j in range(i + 1, len(circles)):
                joint = _enclosing(a, circles[j])
                if best is None or joint.r < best[0].r:
                    best = (joint, i, j)
        joint, i, j = best
        circles = [c for k, c in enumerate(circles) if k not in (i, j)] + [joint]
    return circles


def _enclosing(a: Circle, b: Circle) -> Circle:
    """The smallest circle (m) round circles ``a`` and ``b``."""
    d = math.hypot(b.x - a.x, b.y - a.y)
    if d + b.r <= a.r:
        return a
    if d + a.r <= b.r:
        return b
    r = 0.5 * (d + a.r + b.r)
    t = (r - a.r) / d
    return Circle(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), r)


def _cover(xy: np.ndarray) -> Circle:
    """A circle (m) round the hits ``xy``, ``PAD`` beyond them."""
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    cx, cy = 0.5 * (lo + hi)
    return Circle(float(cx), float(cy), float(np.max(np.hypot(xy[:, 0] - cx, xy[:, 1] - cy))) + PAD)


def _touching(ix: np.ndarray, iy: np.ndarray) -> list[np.ndarray]:
    """Indices into (ix, iy) grouped by cells that touch (edge or corner), transitively."""
    index = {(int(a), int(b)): k for k, (a, b) in enumerate(zip(ix, iy, strict=True))}
    group = [-1] * len(ix)
    groups: list[np.ndarray] = []
    for k0 in range(len(ix)):
        if group[k0] >= 0:
            continue
        group[k0] = len(groups)
        members, todo = [k0], [k0]
        while todo:
            k = todo.pop()
            a, b = int(ix[k]), int(iy[k])
            for da in (-1, 0, 1):
                for db in (-1, 0, 1):
                    j = index.get((a + da, b + db))
                    if j is not None and group[j] < 0:
                        group[j] = len(groups)
                        members.append(j)
                        todo.append(j)
        groups.append(np.array(members))
    return groups
