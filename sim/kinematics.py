"""turtlesim's kinematics as pure functions: no I/O, no clock, no zenoh.

Units: positions in m, headings in rad, linear speed in m/s, angular speed in
rad/s, times in s.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import msgspec

from turtlectl.messages.angles import wrap_radians
from turtlectl.messages.world import Limits, Obstacle

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


def collide(before: TurtleState, after: TurtleState, obstacles: Sequence[Obstacle]) -> tuple[TurtleState, bool]:
    """``after`` (the result of a step from ``before``) stopped at the first declared
    obstacle its straight move would enter, as a wall stops turtlesim's turtle.

    Obstacles are solid circles (m): a move into one ends on its surface with the
    linear speed set to 0, and the second value is True (contact).  A move along
    or away from a surface the turtle touches is free.
    """
    px, py = before.x, before.y
    dx, dy = after.x - px, after.y - py
    length2 = dx * dx + dy * dy
    if length2 == 0.0:
        return after, False
    first = math.inf  # fraction of the move at which it enters an obstacle
    for o in obstacles:
        fx, fy = px - o.x, py - o.y
        towards = fx * dx + fy * dy  # < 0: moving towards the centre
        outside = fx * fx + fy * fy - o.radius * o.radius
        if outside <= 0.0:  # on the surface (or inside by rounding)
            if towards < 0.0:
                first = 0.0
            continue
        disc = towards * towards - length2 * outside
        if towards >= 0.0 or disc < 0.0:
            continue
        t = (-towards - math.sqrt(disc)) / length2
        if t <= 1.0:
            first = min(first, t)
    if first is math.inf:
        return after, False
    return TurtleState(x=px + first * dx, y=py + first * dy, theta=after.theta, v=0.0, w=after.w), True
