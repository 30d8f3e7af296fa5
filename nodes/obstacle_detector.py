"""The obstacle detector process: a mock laser scanner at 5 Hz.

Casts rays from the turtle's pose (``turtle1/pose``, in a namespace its turtle's: the newest one read at each
tick: the 62.5 Hz poses in between never wake this process) against the world's
circles and walls, the other turtles (``turtles``, the newest read at each tick: circles of
the world's turtle radius), plus obstacles it is told the world does not declare and
short-lived phantom detections if asked for
(sim.lidar, numpy), and publishes ``obstacles`` (LaserScan).
"""

from __future__ import annotations

import math

import numpy as np

from turtlectl.messages import LaserScan, Pose, Turtles
from turtlectl.messages.keys import OBSTACLES, POSE, TURTLES
from turtlectl.messages.world import Obstacle, World
from turtlectl.nodes.params import OBSTACLE_DETECTOR_CLAIMS, OBSTACLE_DETECTOR_INTERFACE, ObstacleDetectorParams
from turtlectl.runtime import Node, run_main
from turtlectl.sim.lidar import beam_angles, cast_rays, new_phantoms
from turtlectl.sim.turtles import others


class ObstacleDetector:
    Params = ObstacleDetectorParams
    Claims = OBSTACLE_DETECTOR_CLAIMS
    Interface = OBSTACLE_DETECTOR_INTERFACE

    def __init__(self, node: Node[ObstacleDetectorParams]):
        self.node = node
        p = node.params
        self.pose: Pose | None = None
        self.latest_pose = node.latest(POSE, Pose)
        self.latest_turtles = node.latest(f"/{TURTLES}", Turtles)  # the others are seen too (in any namespace)
        self.rng = np.random.default_rng(p.phantom_seed)
        self.phantoms: list[tuple[float, Obstacle]] = []  # (expiry, monotonic s), obstacle
        self.pub = node.publisher(OBSTACLES, LaserScan)
        self.timer = node.timer(1.0 / p.rate, self.tick)
        self.configure(p)
        node.on_params(self.configure)

    def configure(self, p: ObstacleDetectorParams) -> None:
        """What the scan is made from: beam angles, the obstacles seen, the rate (again after
        ``turtlectl param set``)."""
        self.angles = beam_angles(math.radians(p.angle_min), math.radians(p.angle_max), p.beams)
        self.increment = float(self.angles[1] - self.angles[0]) if p.beams > 1 else 0.0
        self.seen = World(size=self.node.world.size, obstacles=self.node.world.obstacles + p.undeclared_obstacles)
        if self.timer.period != 1.0 / p.rate:
            self.timer.retime(1.0 / p.rate)

    def world(self) -> World:
        """The declared world plus the undeclared obstacles, the phantoms alive now (new ones
        spawned for this tick) and the other turtles (circles of the turtle radius)."""
        p = self.node.params
        extra: list[Obstacle] = []
        if p.phantom_rate > 0 and self.pose is not None:
            now = self.node.clock()
            born = new_phantoms(
                self.rng, self.pose.x, self.pose.y, p.phantom_rate, 1.0 / p.rate, p.phantom_distance, p.phantom_radius
            )
            self.phantoms = [(t, o) for t, o in self.phantoms if t > now] + [
                (now + p.phantom_lifetime, o) for o in born
            ]
            extra += [o for _, o in self.phantoms]
        turtles = self.latest_turtles.get()
        if turtles is not None:
            r = self.node.world.turtle_radius
            extra += [Obstacle(x=x, y=y, radius=r) for _, x, y, _ in others(turtles, but=self.node.turtle)]
        return World(size=self.seen.size, obstacles=self.seen.obstacles + extra) if extra else self.seen

    def tick(self) -> None:
        self.pose = self.latest_pose.get()
        if self.pose is None:
            return
        p = self.node.params
        ranges = cast_rays(self.pose.x, self.pose.y, self.pose.theta, self.angles, self.world(), p.range_max)
        self.pub.publish(
            LaserScan(
                angle_min=float(self.angles[0]),
                angle_max=float(self.angles[-1]),
                angle_increment=self.increment,
                range_min=p.range_min,
                range_max=p.range_max,
                ranges=ranges.tolist(),
                origin_x=self.pose.x,
                origin_y=self.pose.y,
                origin_theta=self.pose.theta,
            )
        )


def main() -> None:
    run_main(ObstacleDetector, ObstacleDetectorParams)


if __name__ == "__main__":
    main()
