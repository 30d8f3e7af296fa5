"""The world every node shares: its size, the obstacles in it, the robot's limits.

Declared once, in the ``[world]`` and ``[limits]`` tables of the launch file,
and handed to every node by the supervisor (one source of truth).
"""

from __future__ import annotations

from typing import Annotated

import msgspec

# Constrained numbers for parameters: validated (with the key path) when a
# launch file is converted; NaN fails every bound, 1e9 stands in for "finite".
Finite = Annotated[float, msgspec.Meta(ge=-1e9, le=1e9)]
Positive = Annotated[float, msgspec.Meta(gt=0.0, le=1e9)]
NonNegative = Annotated[float, msgspec.Meta(ge=0.0, le=1e9)]
Percent = Annotated[float, msgspec.Meta(ge=0.0, le=100.0)]

# Rates and times, bounded so that a typo cannot make a node spin (1e9 Hz) or wait forever:
#: Hz of a node's timer (status 10 Hz, scan 5 Hz, goal feedback 10 Hz): 0.1 to 100.
Rate = Annotated[float, msgspec.Meta(ge=0.1, le=100.0)]
#: s of a watchdog on a fast stream (poses and commands every 16 ms, scans every 200 ms): 0.05 to 60.
ShortTimeout = Annotated[float, msgspec.Meta(ge=0.05, le=60.0)]
#: s of a goal-level limit (blocked, whole goal): 0.1 s to an hour.
LongTimeout = Annotated[float, msgspec.Meta(ge=0.1, le=3600.0)]

#: turtlesim's world: its 500 px canvas is (500 - 1) / 45 m wide; the turtle spawns at the centre.
TURTLESIM_SIZE = (500.0 - 1.0) / 45.0


class Obstacle(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """A circular obstacle: centre (x, y) in m, radius in m."""

    x: Finite
    y: Finite
    radius: Positive


class World(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """A square world from (0, 0) to (size, size), in m, with circular obstacles."""

    size: Positive = TURTLESIM_SIZE
    obstacles: list[Obstacle] = msgspec.field(default_factory=list)

    def contains(self, x: float, y: float) -> bool:
        """True if (x, y), in m, lies inside the world (walls included)."""
        return 0.0 <= x <= self.size and 0.0 <= y <= self.size


class Limits(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """The robot's motion limits; the simulator enforces them, the navigator plans within them.

    max_linear_speed: m/s (either direction).  max_angular_speed: rad/s.
    max_linear_accel: m/s^2 (speeding up and braking).  max_angular_accel: rad/s^2.
    """

    max_linear_speed: Positive = 4.0
    max_angular_speed: Positive = 6.2832
    max_linear_accel: Positive = 10.0
    max_angular_accel: Positive = 40.0
