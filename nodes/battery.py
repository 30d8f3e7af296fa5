"""The simulated battery and the TurtleStatus it feeds, as pure functions.

Units: battery in percent [0, 100], time in s, distance in m, velocities m/s.
"""

from __future__ import annotations

import math

from turtlectl.messages import Pose, TurtleStatus
from turtlectl.messages.angles import heading_degrees


def drain(battery: float, dt: float, distance: float, per_second: float, per_metre: float) -> float:
    """Battery (%) after ``dt`` s in which the turtle travelled ``distance`` m; never below 0."""
    return max(0.0, battery - per_second * dt - per_metre * distance)


#: a move between two poses longer than this many times what the speed limit allows in the
#: time between their stamps is a jump (teleport, reset), not travel
JUMP_FACTOR = 1.5


def travelled(before: Pose, after: Pose, max_speed: float) -> float:
    """Distance (m) driven between two consecutive poses; 0 for a jump that no drive at
    ``max_speed`` m/s could make in the time between their stamps (ns), such as a teleport
    or a reset, which are not travel.  Poses without stamps are taken 0.1 s apart.

    The status monitor calls it with consecutive 62.5 Hz poses.  Poses further apart still
    measure driving (the jump test scales with the stamps' interval, so a 0.1 s drive at the
    speed limit is travel) but let shorter teleports pass as travel; the straight chord between the two poses is shorter than the arc driven only
    while turning, by under 1.7 % at the limits (4 m/s while turning at 2 pi rad/s;
    0.04 % between 62.5 Hz poses); a teleport or reset inside an interval takes that
    interval's driving with it (at most 0.1 s of travel, instead of 16 ms)."""
    distance = math.hypot(after.x - before.x, after.y - before.y)
    dt = (after.stamp - before.stamp) / 1e9 if after.stamp > before.stamp > 0 else 0.1
    return 0.0 if distance > JUMP_FACTOR * max_speed * dt + 1e-6 else distance


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
