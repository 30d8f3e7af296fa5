"""The simulated lidar as pure numpy functions: no I/O, no clock, no zenoh.

Rays start at the turtle's position; angles are rad in the turtle's frame
(0 = straight ahead, counter-clockwise positive); distances are m.  Phantoms
are the sensor's false detections (the mock sensor of docs/capstone.md), drawn from a
seeded generator.
"""

from __future__ import annotations

import math

import numpy as np

from turtlectl.messages.world import Obstacle, World


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


def new_phantoms(
    rng: np.random.Generator, x: float, y: float, rate: float, dt: float, distance: float, radius: float
) -> list[Obstacle]:
    """Phantom obstacles appearing in ``dt`` s at ``rate`` per s (Poisson), each a circle of
    ``radius`` m whose centre is ``distance`` m from (x, y) m in a uniformly random direction."""
    count = int(rng.poisson(rate * dt)) if rate > 0 else 0
    angles = rng.uniform(-math.pi, math.pi, count)
    return [Obstacle(x=x + distance * math.cos(a), y=y + distance * math.sin(a), radius=radius) for a in angles]
