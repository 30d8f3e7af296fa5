"""turtlesim's kinematics as pure functions: no I/O, no clock, no zenoh.

Units: positions in m, headings in rad, linear speed in m/s, angular speed in
rad/s, times in s.
"""

from __future__ import annotations

import math

import msgspec

from messages.angles import wrap_radians
from sim.world import Limits

#: turtlesim updates its turtles every 16 ms (62.5 Hz).
STEP = 0.016
#: turtlesim stops a turtle whose last cmd_vel is older than this, in s.
CMD_TIMEOUT = 1.0


class TurtleState(msgspec.Struct, kw_only=True):
    """Pose and current velocity of the turtle.

    x, y: m.  theta: rad in [-pi, pi).  v: m/s along the heading.  w: rad/s.
    """

    x: float
    y: float
    theta: float
    v: float = 0.0
    w: float = 0.0


#: ``angle`` (rad) wrapped into [-pi, pi), exactly: the one wrap of messages.angles.
wrap_angle = wrap_radians


def effective_command(
    linear: float, angular: float, age: float | None, limits: Limits, timeout: float = CMD_TIMEOUT
) -> tuple[float, float]:
    """The velocity the turtle actually follows, in (m/s, rad/s).

    ``age`` is the time in s since the command arrived (None: no command yet).
    A command older than ``timeout`` is dropped (turtlesim's 1 s rule), a
    non-finite one is ignored, and speeds are clipped to ``limits``.
    """
    if age is None or age > timeout or not (math.isfinite(linear) and math.isfinite(angular)):
        return 0.0, 0.0
    v = min(max(linear, -limits.max_linear_speed), limits.max_linear_speed)
    w = min(max(angular, -limits.max_angular_speed), limits.max_angular_speed)
    return v, w


def accelerate(state: TurtleState, v: float, w: float, dt: float, limits: Limits) -> tuple[float, float]:
    """Speeds (m/s, rad/s) reached after ``dt`` s of pursuing (v, w) from the state's
    current speeds, changing by at most the acceleration limits."""
    dv = limits.max_linear_accel * dt
    dw = limits.max_angular_accel * dt
    return (
        state.v + min(max(v - state.v, -dv), dv),
        state.w + min(max(w - state.w, -dw), dw),
    )


def step(state: TurtleState, v: float, w: float, dt: float, world_size: float) -> TurtleState:
    """Advance the turtle by ``dt`` s at speeds (v m/s, w rad/s), as turtlesim does.

    The heading is integrated first and the position follows the new heading
    (turtlesim's Euler scheme); the position is clamped to the walls
    [0, world_size] m.  A turtle pressed against a wall keeps its commanded
    speed, as in turtlesim.
    """
    theta = wrap_angle(state.theta + w * dt)
    x = state.x + math.cos(theta) * v * dt
    y = state.y + math.sin(theta) * v * dt
    x = min(max(x, 0.0), world_size)
    y = min(max(y, 0.0), world_size)
    return TurtleState(x=x, y=y, theta=theta, v=v, w=w)
