"""Status monitor: turtle1/pose in, robot/status out (this project's TurtleStatus) at 10 Hz,
with a battery that drains as the turtle drives."""

from __future__ import annotations

import math
from typing import Annotated

import msgspec
from capstone_msgs import TurtleStatus

from turtlectl import Interface, Node, run_main
from turtlectl.messages import Pose


class StatusParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    rate: Annotated[float, msgspec.Meta(gt=0.0, le=100.0)] = 10.0  # Hz: statuses a second
    drain_per_metre: Annotated[float, msgspec.Meta(ge=0.0, le=10.0)] = 0.1  # %: battery used per m driven


def status_of(pose: Pose, battery: float) -> TurtleStatus:
    """The status of a turtle at ``pose`` (theta in rad) with ``battery`` %."""
    return TurtleStatus(
        x=pose.x,
        y=pose.y,
        theta=math.degrees(pose.theta) % 360.0,
        vel_x=pose.linear_velocity * math.cos(pose.theta),
        vel_y=pose.linear_velocity * math.sin(pose.theta),
        battery=battery,
    )


class StatusMonitor:
    Params = StatusParams
    Interface = Interface(publishes=("robot/status",), subscribes=("turtle1/pose",))

    def __init__(self, node: Node[StatusParams]):
        self.node = node
        self.battery = 100.0  # %
        self.last: Pose | None = None
        self.pose = node.latest("turtle1/pose", Pose)  # the newest pose, read at our own rate
        self.pub = node.publisher("robot/status", TurtleStatus)
        self.timer = node.timer(1.0 / node.params.rate, self.tick)

    def tick(self) -> None:
        pose = self.pose.get()
        if pose is None:
            return  # nothing to report until the simulator speaks
        if self.last is not None:
            driven = math.hypot(pose.x - self.last.x, pose.y - self.last.y)
            self.battery = max(0.0, self.battery - driven * self.node.params.drain_per_metre)
        self.last = pose
        self.pub.publish(status_of(pose, self.battery))


if __name__ == "__main__":
    run_main(StatusMonitor, StatusParams)
