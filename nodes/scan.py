"""Scan geometry as pure numpy functions: no I/O, no clock, no zenoh.

Rays start at the turtle's position; angles are rad in the turtle's frame
(0 = straight ahead, counter-clockwise positive); distances are m.
"""

from __future__ import annotations

import math

import numpy as np

from sim.world import Obstacle, World


def beam_angles(angle_min: float, angle_max: float, count: int) -> np.ndarray:
    """``count`` beam angles (rad) from angle_min to angle_max; a full circle is not doubled."""
    full_circle = math.isclose(angle_max - angle_min, 2.0 * math.pi)
    return np.linspace(angle_min, angle_max, count, endpoint=not full_circle)


def cast_rays(x: float, y: float, theta: float, angles: np.ndarray, world: World, range_max: float) -> np.ndarray:
    """Distance (m) along each beam to the first circle or wall, ``inf`` beyond ``range_max``.

    (x, y) in m and theta in rad are the turtle's pose; ``angles`` (rad) are
    relative to its heading.  A turtle inside an obstacle reads 0 on every beam.
    """
    world_angles = theta + np.asarray(angles, dtype=float)
    ux, uy = np.cos(world_angles), np.sin(world_angles)

    # Walls: the turtle is inside the box [0, size]^2, so the exit distance is
    # the nearer of the x and y wall crossings along each ray.
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = np.where(ux > 0, (world.size - x) / ux, np.where(ux < 0, -x / ux, np.inf))
        ty = np.where(uy > 0, (world.size - y) / uy, np.where(uy < 0, -y / uy, np.inf))
    hits = np.minimum(tx, ty)

    if world.obstacles:
        circles = np.array([(o.x, o.y, o.radius) for o in world.obstacles], dtype=float)
        cx = circles[:, 0] - x  # (m,)
        cy = circles[:, 1] - y
        r = circles[:, 2]
        # Ray p + t u meets |p + t u - c| = r where t = b -/+ sqrt(b^2 - c2).
        b = ux[:, None] * cx[None, :] + uy[:, None] * cy[None, :]  # (n, m)
        c2 = cx**2 + cy**2 - r**2  # (m,) < 0 when inside
        disc = b**2 - c2[None, :]
        root = np.sqrt(np.clip(disc, 0.0, None))
        t = b - root
        t = np.where((disc >= 0) & (t >= 0), t, np.inf)
        t = np.where(c2[None, :] <= 0, 0.0, t)  # inside a circle
        hits = np.minimum(hits, t.min(axis=1))

    return np.where(hits <= range_max, np.maximum(hits, 0.0), np.inf)


def nearest_in_cone(ranges: np.ndarray, angles: np.ndarray, direction: float, half_width: float) -> float:
    """Smallest range (m) among beams within ``half_width`` rad of ``direction`` rad; inf if none."""
    offset = np.abs((np.asarray(angles) - direction + np.pi) % (2.0 * np.pi) - np.pi)
    selected = np.asarray(ranges, dtype=float)[offset <= half_width]
    return float(selected.min()) if selected.size else math.inf


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


def obstacles_in_view(ranges: np.ndarray, angles: np.ndarray) -> int:
    """Number of separate objects the scan sees: runs of consecutive finite beams."""
    finite = np.isfinite(np.asarray(ranges, dtype=float))
    if not finite.any():
        return 0
    # count rising edges, treating the scan as circular only if it is a full circle
    edges = np.count_nonzero(finite & ~np.roll(finite, 1))
    return int(edges) if edges else 1


def new_phantoms(
    rng: np.random.Generator, x: float, y: float, rate: float, dt: float, distance: float, radius: float
) -> list[Obstacle]:
    """Phantom obstacles appearing in ``dt`` s at ``rate`` per s (Poisson), each a circle of
    ``radius`` m whose centre is ``distance`` m from (x, y) m in a uniformly random direction."""
    count = int(rng.poisson(rate * dt)) if rate > 0 else 0
    angles = rng.uniform(-math.pi, math.pi, count)
    return [
        Obstacle(x=x + distance * math.cos(a), y=y + distance * math.sin(a), radius=radius) for a in angles
    ]
