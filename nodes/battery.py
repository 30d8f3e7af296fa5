"""The simulated battery and the TurtleStatus it feeds, as pure functions.

Units: battery in percent [0, 100], time in s, distance in m, velocities m/s.
"""

from __future__ import annotations

import math

from messages import TurtleStatus
from messages.angles import heading_degrees


def drain(battery: float, dt: float, distance: float, per_second: float, per_metre: float) -> float:
    """Battery (%) after ``dt`` s in which the turtle travelled ``distance`` m; never below 0."""
    return max(0.0, battery - per_second * dt - per_metre * distance)


def make_status(x: float, y: float, theta: float, linear_velocity: float, battery: float) -> TurtleStatus:
    """TurtleStatus from a pose (m, m, rad, m/s): heading in degrees [0, 360), world-frame velocity."""
    return TurtleStatus(
        x=x,
        y=y,
        theta=heading_degrees(theta),
        vel_x=linear_velocity * math.cos(theta),
        vel_y=linear_velocity * math.sin(theta),
        battery=battery,
    )
