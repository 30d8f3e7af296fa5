"""The status monitor process: ``turtle1/pose`` -> ``robot/status`` (TurtleStatus) at 10 Hz.

Publishes on an absolute-deadline schedule (the runtime's timer), so the
period stays 100 ms without drift.  The battery drains with time and with
distance travelled between consecutive 62.5 Hz poses (nodes.battery); jumps
(teleport, reset) are not travel.  Every pose is taken, not the newest at each
tick: 0.1 s apart, a 0.5 m teleport would look like driving.  They wait in
Zenoh between ticks (``Node.latest``'s ring, ``POSES_KEPT``) and are summed at each tick, so
the 62.5 Hz poses wake this process only at its own rate.
"""

from __future__ import annotations

from turtlectl.messages import Ack, Pose, Reset, TurtleStatus
from turtlectl.messages.keys import POSE, RESET, STATUS
from turtlectl.nodes.battery import drain, make_status, travelled
from turtlectl.nodes.params import STATUS_MONITOR_CLAIMS, STATUS_MONITOR_INTERFACE, StatusMonitorParams
from turtlectl.runtime import Node, Request, run_main

FULL = 100.0  # %
#: poses kept between two ticks: 16 s of them at 62.5 Hz (the slowest rate, 0.1 Hz, is 10 s)
POSES_KEPT = 1024


class StatusMonitor:
    Params = StatusMonitorParams
    Claims = STATUS_MONITOR_CLAIMS
    Interface = STATUS_MONITOR_INTERFACE

    def __init__(self, node: Node[StatusMonitorParams]):
        self.node = node
        self.pose: Pose | None = None
        self.battery = node.params.battery
        self.travelled = 0.0  # m since the last status
        self.last_tick: float | None = None  # s, the node's clock (none yet: with use_sim_time, 0 before the clock)
        self.pub = node.publisher(STATUS, TurtleStatus)
        self.poses = node.latest(POSE, Pose, keep=POSES_KEPT)  # every one, read at each tick
        node.serve(f"/{RESET}", Reset, Ack, self.on_reset)  # the world's reset, in any namespace
        self.timer = node.timer(1.0 / node.params.rate, self.tick)
        node.on_params(lambda params: self.timer.retime(1.0 / params.rate))

    def on_reset(self, request: Request[Reset]) -> None:
        self.battery, self.travelled = FULL, 0.0
        request.respond(Ack(detail=f"{self.node.turtle}: battery full"))  # one of a fleet's

    def on_pose(self, pose: Pose) -> None:
        if self.pose is not None:
            self.travelled += travelled(self.pose, pose, self.node.limits.max_linear_speed)
        self.pose = pose

    def tick(self) -> None:
        for pose in self.poses.received():
            self.on_pose(pose)
        now = self.node.clock()
        p = self.node.params
        since = 0.0 if self.last_tick is None else now - self.last_tick
        self.battery = drain(self.battery, since, self.travelled, p.drain_per_second, p.drain_per_metre)
        self.last_tick, self.travelled = now, 0.0
        if self.pose is None:
            return  # nothing to report until the simulator speaks
        pose = self.pose
        self.pub.publish(make_status(pose.x, pose.y, pose.theta, pose.linear_velocity, self.battery))


def main() -> None:
    run_main(StatusMonitor, StatusMonitorParams)


if __name__ == "__main__":
    main()
