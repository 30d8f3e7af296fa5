"""The world every node shares: its size, the obstacles in it, the robot's limits.

Declared once, in the ``[world]`` and ``[limits]`` tables of the launch file,
and handed to every node by the supervisor (one source of truth).
"""

from __future__ import annotations

import msgspec

from turtlectl.messages.units import Finite, Positive

#: turtlesim's world: its 500 px canvas is (500 - 1) / 45 m wide; the turtle spawns at the centre.
TURTLESIM_SIZE = (500.0 - 1.0) / 45.0


class Obstacle(msgspec.Struct, frozen=True, forbid_unknown_fields=True, kw_only=True):
    """A circular obstacle: centre (x, y) in m, radius in m."""

    x: Finite  # m: centre, from the world's left wall
    y: Finite  # m: centre, from the world's bottom wall
    radius: Positive  # m: radius


class World(msgspec.Struct, frozen=True, forbid_unknown_fields=True, kw_only=True):
    """A square world from (0, 0) to (size, size), in m, with circular obstacles."""

    size: Positive = TURTLESIM_SIZE  # m: side of the square world
    obstacles: list[Obstacle] = msgspec.field(default_factory=list)  # -: circles, { x, y, radius } tables
    turtle_radius: Positive = 0.3  # m: a turtle's size to the others: two turtles' centres stay twice this apart

    def contains(self, x: float, y: float) -> bool:
        """True if (x, y), in m, lies inside the world (walls included)."""
        return 0.0 <= x <= self.size and 0.0 <= y <= self.size


class Limits(msgspec.Struct, frozen=True, forbid_unknown_fields=True, kw_only=True):
    """The robot's motion limits; the simulator enforces them, the navigator plans within them.

    max_linear_speed: m/s (either direction).  max_angular_speed: rad/s.
    max_linear_accel: m/s^2 (speeding up and braking).  max_angular_accel: rad/s^2.
    """

    max_linear_speed: Positive = 4.0  # m/s: fastest forwards or backwards
    max_angular_speed: Positive = 6.2832  # rad/s: fastest turn
    max_linear_accel: Positive = 10.0  # m/s^2: speeding up and braking
    max_angular_accel: Positive = 40.0  # rad/s^2: angular acceleration
