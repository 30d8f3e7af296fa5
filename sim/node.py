"""The simulator process: turtlesim's world around sim.kinematics.

It starts with one turtle, ``turtle1`` at the spawn pose of its parameters; ``spawn`` adds
more and ``kill`` removes one, as turtlesim's services do (sim.turtles: where one may go, its
name).  Each turtle has its keys under its name: it takes ``<name>/cmd_vel`` (Twist), is
stepped every 16 ms within the robot's limits, publishes ``<name>/pose`` (Pose) after each
step, and serves ``<name>/teleport_absolute``.  Every 4th step the simulator publishes
``turtles``: every turtle's name and pose.  ``reset`` is turtlesim's: turtle1 back at its
spawn (made again if it was killed), every other turtle removed.

Declared obstacles are solid, as the walls are, and so are the turtles to each other (two
centres stay ``2 * world.turtle_radius`` apart): a turtle driven into one stops on its surface
and its pose says ``contact``.  Before a teleport or reset moves a turtle, the simulator calls
``<turtle>/moving`` (``Moving``, reason "teleported" / "reset"; a reset calls every turtle's)
and moves it once whatever drives the turtle has answered (the navigator ends its running goal
with that reason, so it stops driving from a pose that no longer holds); an Ack (for spawn: its
name) is sent once the new pose has been published, so a goal sent after it starts from there.

The simulator makes the time (runtime.simtime): after every step it publishes ``clock``, its
simulated time (ns since the epoch, from the wall-clock time it started, 16 ms more per step).
``real_time_factor`` sets how fast the steps come: 5 makes a step every 3.2 ms, 5 simulated
seconds per wall second (as fast as the machine allows: a late step is skipped, and the
simulated time with it).  Its own timeouts (``cmd_timeout``) run on the simulated time; its
messages are stamped with it when the system uses it (its ``use_sim_time``, or a factor other
than 1), else with the wall clock as every node's are.
"""

from __future__ import annotations

import math
import time
from typing import Any

import msgspec

from turtlectl.messages import (
    Ack,
    Clock,
    Kill,
    Message,
    Moving,
    Pose,
    Reset,
    SpawnRequest,
    SpawnResponse,
    TeleportAbsolute,
    Turtles,
    Twist,
)
from turtlectl.messages.angles import heading_degrees
from turtlectl.messages.keys import (
    CLOCK,
    FIRST_TURTLE,
    KILL,
    RESET,
    SPAWN,
    TURTLES,
    WORLD_KEY,
    cmd_vel_key,
    moving_key,
    pose_key,
    teleport_key,
)
from turtlectl.messages.world import Obstacle
from turtlectl.runtime import Node, Request, run_main
from turtlectl.runtime.entities import Publisher
from turtlectl.runtime.handles import Declaration
from turtlectl.sim.kinematics import STEP, TurtleState, accelerate, collide, effective_command, step, wrap_angle
from turtlectl.sim.params import SIM_CLAIMS, SIM_INTERFACE, SimParams
from turtlectl.sim.turtles import bodies, free_name, placement_problem, spawn_problem

#: steps between two ``turtles`` messages
TURTLES_EVERY = 4
#: ns: one step of simulated time
STEP_NS = round(STEP * 1e9)


def touches(s: TurtleState, obstacles: list[Obstacle]) -> bool:
    """Whether the turtle's centre lies on a declared obstacle's surface (where a push stops)."""
    return any(abs(math.hypot(s.x - o.x, s.y - o.y) - o.radius) < 1e-6 for o in obstacles)


class Turtle:
    """One turtle: its state, its last command, and its keys (declared under its name; ``remove``
    undeclares them)."""

    def __init__(self, sim: Simulator, name: str, state: TurtleState):
        self.name, self.state = name, state
        self.sim = sim
        self.cmd = Twist()
        self.cmd_time: float | None = None
        self.contact = False
        node = sim.node
        self.pose_pub = node.publisher(pose_key(name), Pose)
        self.declared: list[Publisher[Pose] | Declaration] = [
            self.pose_pub,
            node.subscribe(cmd_vel_key(name), Twist, self.on_cmd_vel),
            node.serve(teleport_key(name), TeleportAbsolute, Ack, lambda request: sim.on_teleport(self, request)),
        ]

    def on_cmd_vel(self, msg: Twist) -> None:
        self.cmd = msg
        self.cmd_time = self.sim.now()

    def remove(self) -> None:
        for declared in self.declared:
            declared.undeclare()


class Simulator:
    Params = SimParams
    Claims = SIM_CLAIMS
    Interface = SIM_INTERFACE

    def __init__(self, node: Node[SimParams]):
        self.node = node
        p = node.params
        self.time_ns = time.time_ns()  # the simulated time: the wall clock's now, 16 ms more per step
        if node.uses_sim_time or p.real_time_factor != 1.0:  # the system runs on it: stamp with it
            node.use_time(lambda: self.time_ns)
        if not node.world.contains(p.x, p.y):
            node.log.warning("spawn (%.3f, %.3f) is outside the world; clamping to the walls", p.x, p.y)
        size = node.world.size
        self.spawn = TurtleState(x=min(max(p.x, 0.0), size), y=min(max(p.y, 0.0), size), theta=wrap_angle(p.theta))
        #: where each turtle of the launch file starts, and is put back by ``reset``
        self.starts: dict[str, TurtleState] = {FIRST_TURTLE: self.spawn} | {
            t.name: TurtleState(x=t.x, y=t.y, theta=wrap_angle(t.theta)) for t in p.turtles
        }
        self.turtles: dict[str, Turtle] = {name: Turtle(self, name, place) for name, place in self.starts.items()}
        self.acks: list[tuple[Request[Any], Message]] = []  # answered once the next pose is out
        self.ticks = 0
        self.turtles_pub = node.publisher(TURTLES, Turtles)
        node.serve(RESET, Reset, Ack, self.on_reset)
        node.serve(SPAWN, SpawnRequest, SpawnResponse, self.on_spawn)
        node.serve(KILL, Kill, Ack, self.on_kill)
        node.answer_json(WORLD_KEY, msgspec.json.encode(node.world))
        self.clock_pub = node.publisher(CLOCK, Clock)
        self.stepper = node.timer(STEP / p.real_time_factor, self.tick)
        node.on_params(self.on_params)

    def on_params(self, params: SimParams) -> None:
        """A new ``real_time_factor`` paces the steps anew (another parameter leaves them be)."""
        if self.stepper.period != STEP / params.real_time_factor:
            self.stepper.retime(STEP / params.real_time_factor)

    def now(self) -> float:
        """The simulated time, s since the epoch."""
        return self.time_ns / 1e9

    def states(self, but: str = "") -> dict[str, TurtleState]:
        return {name: t.state for name, t in self.turtles.items() if name != but}

    def on_spawn(self, request: Request[SpawnRequest]) -> None:
        body = request.body
        name = body.name or free_name(self.turtles)
        problem = spawn_problem(self.node.world, self.states(), name, body.x, body.y, body.theta)
        if problem is not None:
            request.fail(f"cannot spawn: {problem}")
            return
        self.turtles[name] = Turtle(self, name, TurtleState(x=body.x, y=body.y, theta=wrap_angle(body.theta)))
        self.node.log.info("spawned %s at (%g, %g, %g deg)", name, body.x, body.y, heading_degrees(body.theta))
        self.acks.append((request, SpawnResponse(name=name)))

    def on_kill(self, request: Request[Kill]) -> None:
        name = request.body.name
        turtle = self.turtles.pop(name, None)
        if turtle is None:
            request.fail(f"no turtle named {name!r} (turtles: {', '.join(sorted(self.turtles)) or 'none'})")
            return
        turtle.remove()
        self.node.log.info("killed %s", name)
        request.respond(Ack(detail=f"killed {name}"))

    def on_teleport(self, turtle: Turtle, request: Request[TeleportAbsolute]) -> None:
        body = request.body
        problem = placement_problem(self.node.world, body.x, body.y, body.theta, self.states(but=turtle.name))
        if problem is not None:
            request.fail(f"cannot teleport: {problem}")
            return
        place = TurtleState(x=body.x, y=body.y, theta=wrap_angle(body.theta))
        detail = f"teleported to ({body.x:g}, {body.y:g}, {heading_degrees(place.theta):g} deg)"
        self.move(request, {turtle.name: place}, "teleported", detail)

    def on_reset(self, request: Request[Reset]) -> None:
        others = sorted(n for n in self.turtles if n not in self.starts)
        for name in others:
            self.turtles.pop(name).remove()
        removed = f"; removed {', '.join(others)}" if others else ""
        back = "turtle back at its spawn pose" if len(self.starts) == 1 else "turtles back at their spawn poses"
        self.move(request, self.starts, "reset", f"{back}{removed}", moving_key("**"))

    def move(
        self, request: Request[Any], places: dict[str, TurtleState], reason: str, detail: str, moving: str = ""
    ) -> None:
        """Put each turtle of ``places`` there (made again if it is gone) once whatever drives
        them has answered ``Moving`` with ``reason`` (on ``moving``; by default each turtle's own
        ``<name>/moving``); the Ack follows the first pose published there."""

        def apply(_: list[Message]) -> None:
            for name, place in places.items():
                turtle = self.turtles.get(name)
                if turtle is None:
                    turtle = self.turtles[name] = Turtle(self, name, place)
                turtle.state = place
                turtle.cmd_time = None  # a moved turtle stands still until told otherwise
            self.acks.append((request, Ack(detail=detail)))

        keys = [moving] if moving else [moving_key(name) for name in places]

        def tell_next(_: list[Message]) -> None:
            if keys:
                self.node.call(keys.pop(), Moving(reason=reason), tell_next)
            else:
                apply([])

        tell_next([])

    def tick(self) -> None:
        limits, world = self.node.limits, self.node.world
        self.time_ns += STEP_NS
        self.clock_pub.publish(Clock(clock=self.time_ns, real_time_factor=self.node.params.real_time_factor))
        now = self.now()
        for turtle in self.turtles.values():
            age = None if turtle.cmd_time is None else now - turtle.cmd_time
            cmd = turtle.cmd
            v, w = effective_command(cmd.linear, cmd.angular, age, limits, self.node.params.cmd_timeout)
            v, w = accelerate(turtle.state, v, w, STEP, limits)
            moved = step(turtle.state, v, w, STEP, world.size)
            alone = len(self.turtles) == 1  # the step's hot path: no other bodies to gather
            solid = world.obstacles if alone else world.obstacles + bodies(world, self.states(), but=turtle.name)
            turtle.state, contact = collide(turtle.state, moved, solid)
            if contact and not turtle.contact:
                s = turtle.state
                what = "an obstacle" if touches(s, world.obstacles) else "another turtle"
                who = "" if turtle.name == FIRST_TURTLE else f"{turtle.name}: "  # turtle1's line unprefixed
                self.node.log.info("%scontact with %s at (%.3f, %.3f): stopped", who, what, s.x, s.y)
            turtle.contact = contact
            s = turtle.state
            turtle.pose_pub.publish(
                Pose(x=s.x, y=s.y, theta=s.theta, linear_velocity=s.v, angular_velocity=s.w, contact=contact)
            )
        self.ticks += 1
        if self.ticks % TURTLES_EVERY == 0:
            states = self.states()
            self.turtles_pub.publish(
                Turtles(
                    names=list(states),
                    x=[s.x for s in states.values()],
                    y=[s.y for s in states.values()],
                    theta=[s.theta for s in states.values()],
                )
            )
        acks, self.acks = self.acks, []
        for request, ack in acks:
            request.respond(ack)


def main() -> None:
    run_main(Simulator, SimParams)


if __name__ == "__main__":
    main()
