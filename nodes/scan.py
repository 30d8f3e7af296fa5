"""Scan geometry as pure numpy functions: no I/O, no clock, no zenoh.

Rays start at the turtle's position; angles are rad in the turtle's frame
(0 = straight ahead, counter-clockwise positive); distances are m.
"""

from __future__ import annotations

import math

import numpy as np

from turtlectl.messages.world import Obstacle


def hit_points(x: float, y: float, theta: float, ranges: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """World coordinates (m), shape (n, 2), of the finite hits of a scan taken at (x, y, theta)."""
    r = np.asarray(ranges, dtype=float)
    a = np.asarray(angles, dtype=float) + theta
    finite = np.isfinite(r)
    return np.column_stack((x + r[finite] * np.cos(a[finite]), y + r[finite] * np.sin(a[finite])))


def off_walls(points: np.ndarray, size: float, tolerance: float = 0.02) -> np.ndarray:
    """The points (m) that are not on the world's walls: a straight path between two
    points of the (convex) world never crosses a wall, so wall hits never block it."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    inner = (p > tolerance) & (p < size - tolerance)
    return p[inner.all(axis=1)]


def unexplained(points: np.ndarray, obstacles: list[Obstacle], tolerance: float = 0.05) -> np.ndarray:
    """The points (m) farther than ``tolerance`` m from every obstacle's surface, in order:
    the hits of a scan that the declared obstacles do not explain."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    for o in obstacles:
        p = p[np.hypot(p[:, 0] - o.x, p[:, 1] - o.y) > o.radius + tolerance]
    return p


def path_clearance(
    path: np.ndarray,
    along: np.ndarray,
    points: np.ndarray,
    obstacles: list[Obstacle],
    x: float,
    y: float,
    half_width: float,
    slack: float = 0.05,
) -> tuple[float, Obstacle | None]:
    """Distance (m) along a path to where it first comes within ``half_width`` m of a scan
    hit or of a declared obstacle's surface, and that obstacle (None for a hit); (inf, None)
    if it stays clear.  ``path``: its points ahead, shape (n, 2), m, from the turtle's place;
    ``along``: each one's distance along it (m).

    Something nearer the turtle at (x, y) than ``half_width`` already (beside it, behind
    it, or a turtle that has to leave a margin) blocks only where the path would come
    more than ``slack`` m nearer to it than the turtle is now: the way out of a tight spot
    (round it, or away) is never blocked.
    """
    path = np.asarray(path, dtype=float).reshape(-1, 2)
    nearest, which = math.inf, None
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(p) and len(path):
        now = np.hypot(p[:, 0] - x, p[:, 1] - y)
        limit = np.minimum(half_width, now - slack)
        gaps = np.hypot(path[:, None, 0] - p[None, :, 0], path[:, None, 1] - p[None, :, 1])
        hit = np.flatnonzero((gaps < limit[None, :]).any(axis=1))
        if hit.size:
            nearest = float(along[hit[0]])
    for o in obstacles:
        now = math.hypot(x - o.x, y - o.y) - o.radius
        gaps = np.hypot(path[:, 0] - o.x, path[:, 1] - o.y) - o.radius
        hit = np.flatnonzero(gaps < min(half_width, now - slack))
        if hit.size and along[hit[0]] < nearest:
            nearest, which = float(along[hit[0]]), o
    return nearest, which
