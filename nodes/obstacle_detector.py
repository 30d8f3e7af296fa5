"""The obstacle detector process: a mock laser scanner at 5 Hz.

Casts rays from the turtle's pose (``turtle1/pose``) against the world's
circles and walls (nodes.scan, numpy) and publishes ``obstacles`` (LaserScan).
"""

from __future__ import annotations

import math

from messages import LaserScan, Pose
from messages.keys import OBSTACLES, POSE
from nodes.params import ObstacleDetectorParams
from nodes.runtime import Node, run
from nodes.scan import beam_angles, cast_rays


class ObstacleDetector:
    def __init__(self, node: Node[ObstacleDetectorParams]):
        self.node = node
        p = node.params
        self.angles = beam_angles(math.radians(p.angle_min), math.radians(p.angle_max), p.beams)
        self.increment = float(self.angles[1] - self.angles[0]) if p.beams > 1 else 0.0
        self.pose: Pose | None = None
        self.pub = node.publisher(OBSTACLES, LaserScan)
        node.subscribe(POSE, Pose, self.on_pose)
        node.timer(1.0 / p.rate, self.tick)

    def on_pose(self, pose: Pose) -> None:
        self.pose = pose

    def tick(self) -> None:
        if self.pose is None:
            return
        p = self.node.params
        ranges = cast_rays(self.pose.x, self.pose.y, self.pose.theta, self.angles, self.node.world, p.range_max)
        self.pub.publish(
            LaserScan(
                angle_min=float(self.angles[0]),
                angle_max=float(self.angles[-1]),
                angle_increment=self.increment,
                range_min=p.range_min,
                range_max=p.range_max,
                ranges=ranges.tolist(),
            )
        )


def main() -> None:
    run(ObstacleDetector, ObstacleDetectorParams)


if __name__ == "__main__":
    main()
