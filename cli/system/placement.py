"""Where things may be in a launch file's world, and what a namespace may be called (pure:
no zenoh): the checks of the file as a whole that cli.system.launchfile runs after each value's
own type and range.  Each takes the ``Report`` that names the key path of a mistake.

Units: m and rad.
"""

from __future__ import annotations

import math
from typing import Any

from turtlectl.messages.codec import type_name
from turtlectl.messages.keys import FIRST_TURTLE, SERVICES, TOPICS, includes, key_problem, resolve
from turtlectl.messages.world import World
from turtlectl.runtime.config import Interface
from turtlectl.sim.kinematics import TurtleState
from turtlectl.sim.turtles import NAME as TURTLE_NAME
from turtlectl.sim.turtles import RESERVED, spawn_problem


def namespace_problem(namespace: str) -> str | None:
    """Why ``namespace`` cannot be one (None: it can): a turtle's name (sim.turtles.NAME), the
    turtle its nodes drive."""
    if not TURTLE_NAME.match(namespace):
        return (
            f"{namespace!r} is not a namespace: the name of the turtle its nodes drive "
            "(a letter or _, then letters, digits, _ or -; e.g. turtle2)"
        )
    if namespace in RESERVED:
        return f"{namespace!r} is the first part of the system's own keys; choose another"
    return None


def remap_problem(remap: dict[str, str], namespace: str, interface: Interface | None) -> tuple[str, str] | None:
    """The first ``remap = { FROM = TO }`` entry of a node in ``namespace`` that cannot be, and
    why (None: all can): FROM and TO must be keys (no wildcard), never the runtime's own
    (``turtlectl/...``: every tool finds each node there), no two FROMs the same key; and with
    the node's ``interface`` (its kind's, resolved; None: a user's kind that declares none), FROM
    must be a key the node uses (ROS would ignore it silently: a typo here is an error)."""
    seen: dict[str, str] = {}
    used = [] if interface is None else [k for f in interface.__struct_fields__ for k in getattr(interface, f)]
    for source, target in remap.items():
        resolved: list[str] = []
        for written in (source, target):
            why = key_problem(written)
            if why is None:
                resolved.append(resolve(written, namespace))
                if resolved[-1].startswith("turtlectl/"):
                    why = f"{written} is one of the runtime's own keys (turtlectl/...): they are not remapped"
            if why:
                return source, why
        key, to = resolved
        if key in seen:
            return source, f"{seen[key]} remaps the same key ({key})"
        seen[key] = source
        types = (_type_of(key), _type_of(to))
        if types[0] and types[1] and types[0] != types[1]:
            return source, (
                f"{key} carries {types[0]} and {to} carries {types[1]}: a remap joins keys of one message type"
            )
        if interface is not None and not any(includes(k, key) for k in used):
            hint = (
                f"; write a key as the node's code does ({FIRST_TURTLE}/cmd_vel, robot/status: resolved in its "
                f"namespace, {namespace}) or absolute (/{namespace}/cmd_vel)"
                if namespace
                else ""
            )
            listed = [k for k in dict.fromkeys(used) if not k.startswith("@") and "*" not in k]  # not remappable
            return source, f"the node uses no key {key} (its keys: {', '.join(listed)}){hint}"
    return None


def _type_of(key: str) -> str | None:
    """The message type a known key carries (a resolved key: turtle2/pose is Pose, as turtle1/pose
    is; a service's key, its request's), None: a key of no known type."""
    first = key.partition("/")[0]
    for known, message in TOPICS.items():
        if key in (known, resolve(known, first)):
            return type_name(message)
    for known, (request, _) in SERVICES.items():
        if key in (known, resolve(known, first)):
            return type_name(request)
    return None


def check_turtles(world: World, i: int, sim: dict[str, Any], report: Any) -> None:
    """The simulator's other turtles at start: good names, none taken twice, each where a
    spawn could put it (sim.turtles)."""
    states = {FIRST_TURTLE: TurtleState(x=sim["x"], y=sim["y"], theta=sim["theta"])}
    for j, turtle in enumerate(sim["turtles"]):
        problem = spawn_problem(world, states, turtle["name"], turtle["x"], turtle["y"], turtle["theta"])
        if problem is not None:
            raise report.error(["node", i, "params", "turtles", j], problem)
        states[turtle["name"]] = TurtleState(x=turtle["x"], y=turtle["y"], theta=turtle["theta"])


def check_world(world: World, report: Any) -> None:
    """Obstacles that make no sense in this world: covering all of it, or entirely outside it."""
    size = world.size
    for j, o in enumerate(world.obstacles):
        corners = ((0.0, 0.0), (size, 0.0), (0.0, size), (size, size))
        if all(math.hypot(cx - o.x, cy - o.y) <= o.radius for cx, cy in corners):
            raise report.error(
                ["world", "obstacles", j],
                f"covers the whole world (centre ({o.x:g}, {o.y:g}), radius {o.radius:g} m; the world is {size:g} m square)",
            )
        nearest_x, nearest_y = min(max(o.x, 0.0), size), min(max(o.y, 0.0), size)
        if math.hypot(o.x - nearest_x, o.y - nearest_y) >= o.radius:
            raise report.error(
                ["world", "obstacles", j],
                f"centre ({o.x:g}, {o.y:g}), radius {o.radius:g} m lies entirely outside the world (0 to {size:g} m)",
            )


def check_spawn(world: World, i: int, sim: dict[str, Any], report: Any) -> None:
    """The simulator's spawn: inside the world and outside every obstacle (the node itself
    would only clamp it to the walls, or leave the turtle stuck in an obstacle)."""
    x, y = sim["x"], sim["y"]
    for key, value in (("x", x), ("y", y)):
        if not 0.0 <= value <= world.size:
            raise report.error(
                ["node", i, "params", key], f"spawn {key} = {value:g} m is outside the world (0 to {world.size:g} m)"
            )
    for j, o in enumerate(world.obstacles):
        if math.hypot(x - o.x, y - o.y) <= o.radius:
            raise report.error(
                ["node", i, "params"],
                f"spawn ({x:g}, {y:g}) is inside world.obstacles[{j}] (centre ({o.x:g}, {o.y:g}), radius {o.radius:g} m)",
            )
