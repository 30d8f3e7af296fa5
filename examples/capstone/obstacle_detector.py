"""Obstacle detector: a mock laser scan on ``obstacles`` at 5 Hz, as the lesson's
``sensor_msgs/LaserScan`` mock: every beam clear, but for a simulated detection now and then."""

from __future__ import annotations

import math
import random
from typing import Annotated

import msgspec

from turtlectl import Interface, Node, run_main
from turtlectl.messages import LaserScan


class DetectorParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    rate: Annotated[float, msgspec.Meta(gt=0.0, le=100.0)] = 5.0  # Hz: scans a second
    beams: Annotated[int, msgspec.Meta(ge=1, le=3600)] = 36  # -: rays in a scan
    range_max: Annotated[float, msgspec.Meta(gt=0.0, le=100.0)] = 10.0  # m: farthest a beam sees
    detect_chance: Annotated[float, msgspec.Meta(ge=0.0, le=1.0)] = 0.1  # -: share of scans with a detection


def mock_scan(beams: int, range_max: float, hit: tuple[int, float] | None) -> LaserScan:
    """A scan all round the turtle: ``inf`` (nothing) on every beam, but ``hit``'s (beam, m)."""
    ranges = [math.inf] * beams
    if hit is not None:
        ranges[hit[0]] = hit[1]
    step = 2 * math.pi / beams
    return LaserScan(
        angle_min=-math.pi, angle_max=math.pi - step, angle_increment=step, range_min=0.1, range_max=range_max,
        ranges=ranges,
    )  # fmt: skip


class ObstacleDetector:
    Params = DetectorParams
    Interface = Interface(publishes=("obstacles",))

    def __init__(self, node: Node[DetectorParams]):
        self.node = node
        self.draw = random.Random(1)
        self.pub = node.publisher("obstacles", LaserScan)
        self.timer = node.timer(1.0 / node.params.rate, self.tick)

    def tick(self) -> None:
        p = self.node.params
        hit = None
        if self.draw.random() < p.detect_chance:
            hit = (self.draw.randrange(p.beams), self.draw.uniform(0.5, p.range_max))
        self.pub.publish(mock_scan(p.beams, p.range_max, hit))


if __name__ == "__main__":
    run_main(ObstacleDetector, DetectorParams)
