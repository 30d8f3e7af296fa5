"""Wanderer: drives straight ahead and turns away from what the obstacle detector's scan sees
ahead (a bump-and-turn robot; it publishes ``turtle1/cmd_vel`` itself, so it runs without the
navigator: ``wander.toml``)."""

from __future__ import annotations

import math
from typing import Annotated

import msgspec

from turtlectl import Node, run_main
from turtlectl.messages import LaserScan, Twist


class WanderParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    speed: Annotated[float, msgspec.Meta(ge=0.0, le=2.0)] = 0.8  # m/s: forward speed when clear
    turn: Annotated[float, msgspec.Meta(ge=-3.0, le=3.0)] = 1.5  # rad/s: yaw rate while turning away
    clearance: Annotated[float, msgspec.Meta(gt=0.0, le=5.0)] = 0.8  # m: turn when something is this close ahead
    cone: Annotated[float, msgspec.Meta(gt=0.0, le=180.0)] = 30.0  # degrees: "ahead" is within this of straight on
    rate: Annotated[float, msgspec.Meta(gt=0.0, le=50.0)] = 10.0  # Hz: commands a second


def nearest_ahead(scan: LaserScan, cone_deg: float) -> float:
    """The shortest range within ``cone_deg`` degrees of straight ahead, m (inf: nothing)."""
    cone = math.radians(cone_deg)
    ahead = [r for i, r in enumerate(scan.ranges) if abs(scan.angle_min + i * scan.angle_increment) <= cone]
    return min(ahead, default=math.inf)


def command(scan: LaserScan | None, p: WanderParams) -> Twist:
    """Forward while the way ahead is clear, else turn on the spot; stand still without a scan."""
    if scan is None:
        return Twist(linear=0.0, angular=0.0)
    if nearest_ahead(scan, p.cone) < p.clearance:
        return Twist(linear=0.0, angular=p.turn)
    return Twist(linear=p.speed, angular=0.0)


class Wanderer:
    Params = WanderParams

    def __init__(self, node: Node[WanderParams]):
        self.node = node
        self.scan = node.latest("obstacles", LaserScan)  # the newest scan, read at our own rate
        self.cmd = node.publisher("turtle1/cmd_vel", Twist)
        self.timer = node.timer(1.0 / node.params.rate, self.tick)
        node.on_params(lambda p: self.timer.retime(1.0 / p.rate))
        node.on_shutdown(lambda: self.cmd.publish(Twist(linear=0.0, angular=0.0)))

    def tick(self) -> None:
        self.cmd.publish(command(self.scan.get(), self.node.params))


if __name__ == "__main__":
    run_main(Wanderer, WanderParams)
