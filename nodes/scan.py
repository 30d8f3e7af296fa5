"""Scan geometry as pure numpy functions: no I/O, no clock, no zenoh.

Rays start at the turtle's position; angles are rad in the turtle's frame
(0 = straight ahead, counter-clockwise positive); distances are m.
"""

from __future__ import annotations

import math

import numpy as np

from messages.world import Obstacle


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


def corridor_clearance(points: np.ndarray, x: float, y: float, heading: float, half_width: float) -> float:
    """Distance (m) along ``heading`` (rad, world frame) from (x, y) to the nearest point inside
    the straight corridor of ``half_width`` m either side of that line; inf if it is clear.

    Points beside the path (something the turtle drives along) do not count, unlike a cone's.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    dx, dy = p[:, 0] - x, p[:, 1] - y
    along = dx * math.cos(heading) + dy * math.sin(heading)
    across = np.abs(-dx * math.sin(heading) + dy * math.cos(heading))
    ahead = along[(along > 0.0) & (across <= half_width)]
    return float(ahead.min()) if ahead.size else math.inf


def circles_corridor_clearance(
    obstacles: list[Obstacle], x: float, y: float, heading: float, half_width: float
) -> tuple[float, Obstacle | None]:
    """As ``corridor_clearance``, for the declared circles themselves instead of scan hits:
    the distance (m) along ``heading`` (rad) from (x, y) to the nearest point of any circle
    inside the corridor of ``half_width`` m, and that circle; (inf, None) if none is ahead.

    A circle whose centre lies ``a`` m along and ``c`` m across the line meets the corridor
    iff c - r <= half_width; its points there span a -/+ sqrt(r^2 - max(0, c - half_width)^2).
    """
    cos_h, sin_h = math.cos(heading), math.sin(heading)
    nearest, which = math.inf, None
    for o in obstacles:
        dx, dy = o.x - x, o.y - y
        along = dx * cos_h + dy * sin_h
        outside = max(0.0, abs(-dx * sin_h + dy * cos_h) - half_width)
        if outside > o.radius:
            continue
        half_chord = math.sqrt(o.radius * o.radius - outside * outside)
        if along + half_chord <= 0.0:  # wholly behind
            continue
        start = max(0.0, along - half_chord)
        if start < nearest:
            nearest, which = start, o
    return nearest, which
