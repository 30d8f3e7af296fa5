"""Goal checks for the navigator as pure functions: no I/O, no zenoh.

Units: m, degrees for the request's heading, rad inside.
"""

from __future__ import annotations

import math

from messages import NavigateToRequest
from sim.world import World


def goal_problem(request: NavigateToRequest, world: World) -> str | None:
    """Why ``request`` cannot be a goal in ``world``, or None if it can."""
    for name in ("x", "y", "theta"):
        value = getattr(request, name)
        if not math.isfinite(value):
            return f"invalid goal: {name} is {value}"
    if not world.contains(request.x, request.y):
        return f"invalid goal: ({request.x:g}, {request.y:g}) is outside the world [0, {world.size:.10g}] m"
    for obstacle in world.obstacles:
        if math.hypot(request.x - obstacle.x, request.y - obstacle.y) <= obstacle.radius:
            return f"invalid goal: ({request.x:g}, {request.y:g}) is inside an obstacle"
    return None


def heading_error_deg(goal_theta: float, theta: float) -> float:
    """Absolute difference between two headings in rad, in degrees [0, 180]."""
    return abs(math.degrees(math.remainder(goal_theta - theta, 2.0 * math.pi)))


def clearance_speed(clearance: float, safety_distance: float, decel: float) -> float:
    """Fastest speed (m/s) from which braking at ``decel`` m/s^2 still stops
    ``safety_distance`` m short of an obstacle ``clearance`` m away."""
    return math.sqrt(2.0 * decel * max(0.0, clearance - safety_distance))
