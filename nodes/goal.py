"""Goal checks for the navigator as pure functions: no I/O, no zenoh.

Units: m, degrees for the request's heading, rad inside.
"""

from __future__ import annotations

import math

from messages import NavigateToRequest
from messages.world import World
from nodes.scan import circles_corridor_clearance


def goal_problem(request: NavigateToRequest, world: World) -> str | None:
    """Why ``request`` cannot be a goal in ``world``, or None if it can."""
    for name in ("x", "y", "theta"):
        value = getattr(request, name)
        if not math.isfinite(value):
            return f"invalid goal: {name} is {value} (finite numbers only; theta in degrees, any finite value)"
    if not world.contains(request.x, request.y):
        return f"invalid goal: ({request.x:g}, {request.y:g}) is outside the world [0, {world.size:.10g}] m"
    for obstacle in world.obstacles:
        if math.hypot(request.x - obstacle.x, request.y - obstacle.y) <= obstacle.radius:
            return f"invalid goal: ({request.x:g}, {request.y:g}) is inside an obstacle"
    return None


def path_problem(x: float, y: float, goal_x: float, goal_y: float, world: World, half_width: float) -> str | None:
    """Why the navigator, which drives straight lines, could never reach (goal_x, goal_y)
    from (x, y) (m): a declared obstacle lies in the corridor of ``half_width`` m either
    side of the way before the goal, so it would stop short of it until "blocked".
    None if the way is clear."""
    distance = math.hypot(goal_x - x, goal_y - y)
    if distance == 0.0:
        return None
    bearing = math.atan2(goal_y - y, goal_x - x)
    clearance, obstacle = circles_corridor_clearance(world.obstacles, x, y, bearing, half_width)
    if obstacle is None or clearance >= distance:
        return None
    touching = clearance < 0.01
    where = "right beside the turtle" if touching else f"{clearance:.2f} m ahead"
    return (
        f"unreachable: the straight way from ({x:.2f}, {y:.2f}) to ({goal_x:g}, {goal_y:g}) meets the obstacle "
        f"at ({obstacle.x:g}, {obstacle.y:g}), radius {obstacle.radius:g} m, {where} "
        f"(the navigator drives straight lines and keeps a {2 * half_width:g} m corridor clear): "
        f"send a goal {'away from' if touching else 'beside'} it first"
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
