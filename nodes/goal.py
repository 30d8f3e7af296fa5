"""Goal checks for the navigator as pure functions: no I/O, no zenoh.

Units: m, degrees for the request's heading, rad inside.
"""

from __future__ import annotations

import math

from turtlectl.messages import NavigateToRequest
from turtlectl.messages.world import World


def goal_problem(request: NavigateToRequest, world: World, keep: float = 0.0) -> str | None:
    """Why ``request`` cannot be a goal in ``world`` (a sentence for the response's detail; its
    reason is "invalid goal"), or None if it can: the turtle keeps
    ``keep`` m (its size and a margin) from every obstacle, so a goal nearer one is refused."""
    for name in ("x", "y", "theta"):
        value = getattr(request, name)
        if not math.isfinite(value):
            return f"{name} is {value} (finite numbers only; theta in degrees, any finite value)"
    if not world.contains(request.x, request.y):
        return f"({request.x:g}, {request.y:g}) is outside the world [0, {world.size:.10g}] m"
    for obstacle in world.obstacles:
        gap = math.hypot(request.x - obstacle.x, request.y - obstacle.y) - obstacle.radius
        if gap <= 0.0:
            return f"({request.x:g}, {request.y:g}) is inside an obstacle"
        if gap < keep:
            return (
                f"({request.x:g}, {request.y:g}) is {gap:.2f} m from the obstacle at "
                f"({obstacle.x:g}, {obstacle.y:g}), radius {obstacle.radius:g} m: the turtle keeps {keep:g} m "
                "from obstacles (the navigator's robot_radius + clearance)"
            )
    return None


def no_way(x: float, y: float, goal_x: float, goal_y: float, keep: float, walled_in: str) -> str:
    """Why a goal is refused as "unreachable" when no path reaches it from (x, y) (m), a
    sentence for the response's detail; ``walled_in``
    names what the obstacles enclose ("the goal", "the turtle")."""
    return (
        f"no way from ({x:.2f}, {y:.2f}) to ({goal_x:g}, {goal_y:g}) keeps {keep:g} m from every "
        f"obstacle (the navigator's robot_radius + clearance): {walled_in} is walled in by obstacles"
    )


def allowed_speed(clearance: float, distance_to_goal: float, safety_distance: float, decel: float) -> float:
    """Fastest speed (m/s) allowed with the nearest obstacle ``clearance`` m ahead in the
    corridor: no limit if it lies beyond the goal, 0 within ``safety_distance`` m (blocked),
    else what still brakes ``safety_distance`` short of it at ``decel`` m/s^2."""
    if clearance >= distance_to_goal:
        return math.inf
    if clearance <= safety_distance:
        return 0.0
    return clearance_speed(clearance, safety_distance, decel)


def clearance_speed(clearance: float, safety_distance: float, decel: float) -> float:
    """Fastest speed (m/s) from which braking at ``decel`` m/s^2 still stops
    ``safety_distance`` m short of an obstacle ``clearance`` m away."""
    return math.sqrt(2.0 * decel * max(0.0, clearance - safety_distance))
