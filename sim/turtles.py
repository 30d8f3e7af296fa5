"""Several turtles in one world, as turtlesim's ``spawn`` and ``kill`` make them: where a new
one may go, its name, and the others as solid bodies to each one.  Pure: no I/O, no clock.

Units: m and rad.  Two turtles' centres stay at least ``2 * world.turtle_radius`` apart (each
is solid to the others, as a declared obstacle is); a turtle's own keys are under its name
(messages.keys: ``<name>/cmd_vel``, ``<name>/pose``, ``<name>/teleport_absolute``)."""

from __future__ import annotations

import math
from collections.abc import Mapping

from turtlectl.messages import Turtles
from turtlectl.messages.world import Obstacle, World
from turtlectl.runtime.client.checks import TURTLE_NAME
from turtlectl.sim.kinematics import TurtleState

#: a turtle's name: one key chunk, as a launch file's node names (no '/', '*', '$', '@' start)
NAME = TURTLE_NAME
#: first chunks of the system's own keys: no turtle is called so (its keys would mix with them)
RESERVED = frozenset({"turtlectl", "robot", "navigate_to", "obstacles", "reset", "spawn", "kill", "turtles", "clock"})


def free_name(turtles: Mapping[str, object]) -> str:
    """turtlesim's name for an unnamed spawn: ``turtleN`` with the smallest N >= 1 not taken."""
    n = 1
    while f"turtle{n}" in turtles:
        n += 1
    return f"turtle{n}"


def placement_problem(
    world: World, x: float, y: float, theta: float, others: Mapping[str, TurtleState] = {}
) -> str | None:
    """Why a turtle cannot be put at (x m, y m, theta rad) among ``others`` (by name), or None."""
    for name, value in (("x", x), ("y", y), ("theta", theta)):
        if not math.isfinite(value):
            return f"{name} is {value}"
    if not world.contains(x, y):
        return f"({x:g}, {y:g}) is outside the world [0, {world.size:.10g}] m"
    for o in world.obstacles:
        if math.hypot(x - o.x, y - o.y) < o.radius:  # on the surface is fine: where a push stops
            return f"({x:g}, {y:g}) is inside an obstacle"
    reach = 2.0 * world.turtle_radius
    for name, s in others.items():
        gap = math.hypot(x - s.x, y - s.y)
        if gap < reach - 1e-9:  # touching is fine (where a push stops), rounding included
            return f"({x:g}, {y:g}) is {gap:.2f} m from {name}, nearer than two turtle radii ({reach:g} m)"
    return None


def spawn_problem(
    world: World, turtles: Mapping[str, TurtleState], name: str, x: float, y: float, theta: float
) -> str | None:
    """Why turtle ``name`` cannot be spawned at (x, y, theta), or None."""
    if not NAME.match(name):
        return f"{name!r} is not a turtle name (a letter or _, then letters, digits, _ or -; at most 63)"
    if name in RESERVED:
        return f"{name!r} is the first part of the system's own keys ({name}/...); choose another name"
    if name in turtles:
        return f"a turtle named {name} exists"
    return placement_problem(world, x, y, theta, turtles)


def others(turtles: Turtles, but: str) -> list[tuple[str, float, float, float]]:
    """Every turtle of a ``turtles`` message but ``but``: (name, x m, y m, theta rad)."""
    rows = zip(turtles.names, turtles.x, turtles.y, turtles.theta, strict=False)
    return [(n, x, y, theta) for n, x, y, theta in rows if n != but]


def bodies(world: World, turtles: Mapping[str, TurtleState], but: str) -> list[Obstacle]:
    """The other turtles, as turtle ``but`` meets them: circles of twice the turtle radius round
    their centres (its own centre stops on their surface)."""
    reach = 2.0 * world.turtle_radius
    return [Obstacle(x=s.x, y=s.y, radius=reach) for name, s in turtles.items() if name != but]
