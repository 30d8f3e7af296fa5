"""The simulator process: turtlesim's world around sim.kinematics.

Subscribes ``turtle1/cmd_vel`` (Twist), steps the turtle every 16 ms and
publishes ``turtle1/pose`` (Pose) after each step, as turtlesim does.
"""

from __future__ import annotations

import time

from messages import Pose, Twist
from messages.keys import CMD_VEL, POSE
from nodes.runtime import Node, run
from sim.kinematics import STEP, TurtleState, effective_command, step, wrap_angle
from sim.params import SimParams


class Simulator:
    def __init__(self, node: Node[SimParams]):
        self.node = node
        p = node.params
        if not node.world.contains(p.x, p.y):
            node.log.warning("spawn (%.3f, %.3f) is outside the world; clamping to the walls", p.x, p.y)
        size = node.world.size
        self.state = TurtleState(x=min(max(p.x, 0.0), size), y=min(max(p.y, 0.0), size), theta=wrap_angle(p.theta))
        self.cmd = Twist()
        self.cmd_time: float | None = None
        self.pose_pub = node.publisher(POSE, Pose)
        node.subscribe(CMD_VEL, Twist, self.on_cmd_vel)
        node.timer(STEP, self.tick)

    def on_cmd_vel(self, msg: Twist) -> None:
        self.cmd = msg
        self.cmd_time = time.monotonic()

    def tick(self) -> None:
        age = None if self.cmd_time is None else time.monotonic() - self.cmd_time
        v, w = effective_command(self.cmd.linear, self.cmd.angular, age, self.node.limits, self.node.params.cmd_timeout)
        self.state = step(self.state, v, w, STEP, self.node.world.size)
        s = self.state
        self.pose_pub.publish(Pose(x=s.x, y=s.y, theta=s.theta, linear_velocity=s.v, angular_velocity=s.w))


def main() -> None:
    run(Simulator, SimParams)


if __name__ == "__main__":
    main()
