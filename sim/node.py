"""The simulator process: turtlesim's world around sim.kinematics.

Subscribes ``turtle1/cmd_vel`` (Twist), steps the turtle every 16 ms within
the robot's limits and publishes ``turtle1/pose`` (Pose) after each step, as
turtlesim does.  Serves turtlesim's ``turtle1/teleport_absolute`` and ``reset``.

Declared obstacles are solid, as the walls are: a turtle driven into one stops
on its surface and its pose says ``contact``.  A teleport or reset first cancels
a running goal (reason "teleported" / "reset", so the navigator stops driving
from a pose that no longer holds), then moves the turtle; its Ack is sent once
the new pose has been published, so a goal sent after the Ack starts from it.
"""

from __future__ import annotations

import math
import time
from typing import Any

import msgspec

from turtlectl.messages import Ack, Cancel, Message, Pose, Reset, TeleportAbsolute, Twist
from turtlectl.messages.angles import heading_degrees
from turtlectl.messages.keys import CANCEL, CMD_VEL, POSE, RESET, TELEPORT, WORLD_KEY
from turtlectl.messages.world import World
from turtlectl.runtime import Node, Request, run_main
from turtlectl.sim.kinematics import STEP, TurtleState, accelerate, collide, effective_command, step, wrap_angle
from turtlectl.sim.params import SimParams


def placement_problem(world: World, x: float, y: float, theta: float) -> str | None:
    """Why the turtle cannot be put at (x m, y m, theta rad), or None."""
    for name, value in (("x", x), ("y", y), ("theta", theta)):
        if not math.isfinite(value):
            return f"{name} is {value}"
    if not world.contains(x, y):
        return f"({x:g}, {y:g}) is outside the world [0, {world.size:.10g}] m"
    for o in world.obstacles:
        if math.hypot(x - o.x, y - o.y) < o.radius:  # on the surface is fine: where a push stops
            return f"({x:g}, {y:g}) is inside an obstacle"
    return None


class Simulator:
    def __init__(self, node: Node[SimParams]):
        self.node = node
        p = node.params
        if not node.world.contains(p.x, p.y):
            node.log.warning("spawn (%.3f, %.3f) is outside the world; clamping to the walls", p.x, p.y)
        size = node.world.size
        self.spawn = TurtleState(x=min(max(p.x, 0.0), size), y=min(max(p.y, 0.0), size), theta=wrap_angle(p.theta))
        self.state = self.spawn
        self.cmd = Twist()
        self.cmd_time: float | None = None
        self.contact = False
        self.acks: list[tuple[Request[Any], Ack]] = []  # answered once the next pose is out
        self.pose_pub = node.publisher(POSE, Pose)
        node.subscribe(CMD_VEL, Twist, self.on_cmd_vel)
        node.serve(TELEPORT, TeleportAbsolute, Ack, self.on_teleport)
        node.serve(RESET, Reset, Ack, self.on_reset)
        world_json = msgspec.json.encode(node.world)
        node.answer_json(WORLD_KEY, world_json)
        node.timer(STEP, self.tick)

    def on_cmd_vel(self, msg: Twist) -> None:
        self.cmd = msg
        self.cmd_time = time.monotonic()

    def on_teleport(self, request: Request[TeleportAbsolute]) -> None:
        body = request.body
        problem = placement_problem(self.node.world, body.x, body.y, body.theta)
        if problem is not None:
            request.fail(f"cannot teleport: {problem}")
            return
        place = TurtleState(x=body.x, y=body.y, theta=wrap_angle(body.theta))
        detail = f"teleported to ({body.x:g}, {body.y:g}, {heading_degrees(place.theta):g} deg)"
        self.move(request, place, "teleported", detail)

    def on_reset(self, request: Request[Reset]) -> None:
        self.move(request, self.spawn, "reset", "turtle back at its spawn pose")

    def move(self, request: Request[Any], place: TurtleState, reason: str, detail: str) -> None:
        """Put the turtle at ``place`` once a running goal is canceled (with ``reason``);
        the Ack follows the first pose published there."""

        def apply(_: list[Message]) -> None:
            self.state = place
            self.cmd_time = None  # a moved turtle stands still until told otherwise
            self.acks.append((request, Ack(detail=detail)))

        self.node.call(CANCEL, Cancel(reason=reason), apply)

    def tick(self) -> None:
        age = None if self.cmd_time is None else time.monotonic() - self.cmd_time
        limits = self.node.limits
        v, w = effective_command(self.cmd.linear, self.cmd.angular, age, limits, self.node.params.cmd_timeout)
        v, w = accelerate(self.state, v, w, STEP, limits)
        moved = step(self.state, v, w, STEP, self.node.world.size)
        self.state, contact = collide(self.state, moved, self.node.world.obstacles)
        if contact and not self.contact:
            self.node.log.info("contact with an obstacle at (%.3f, %.3f): stopped", self.state.x, self.state.y)
        self.contact = contact
        s = self.state
        self.pose_pub.publish(
            Pose(x=s.x, y=s.y, theta=s.theta, linear_velocity=s.v, angular_velocity=s.w, contact=contact)
        )
        acks, self.acks = self.acks, []
        for request, ack in acks:
            request.respond(ack)


def main() -> None:
    run_main(Simulator, SimParams)


if __name__ == "__main__":
    main()
