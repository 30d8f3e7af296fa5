"""What the navigator knows of the turtle's surroundings, and the shortest way through them:
pure, the clock passed in.

The world's declared obstacles, always; and what the scans have seen that the world does
not declare (nodes.costmap: remembered where it was seen, forgotten when beams pass through
where it was), used while the latest scan is recent (``scan_timeout``).  Each is kept
``robot_radius + clearance`` away: a path (nodes.planner) goes round them all, and through
no gap between one and a wall too narrow for the turtle.

Shared by the goals one navigator runs: the goal lifecycle (nodes.goal_machine) asks it
whether a goal is reachable at all; the local planner and driver (nodes.driver) plans and
slows with it.

Units: m, s; rad.
"""

from __future__ import annotations

import math

import numpy as np

from turtlectl.messages import LaserScan, Pose
from turtlectl.messages.keys import FIRST_TURTLE
from turtlectl.messages.world import World
from turtlectl.nodes.costmap import HIT_PAD, Costmap
from turtlectl.nodes.params import NavigatorParams
from turtlectl.nodes.planner import Circle, Path, containing, escape, inflate, shortest_path, wall_plugs
from turtlectl.nodes.scan import hit_points, off_walls, unexplained
from turtlectl.nodes.traffic import STANDING, Traffic


class Surroundings:
    """The declared obstacles, the latest scan and the costmap, and planning through them."""

    def __init__(self, params: NavigatorParams, world: World, turtle: str = FIRST_TURTLE):
        self.world = world
        self.traffic = Traffic(turtle, world.turtle_radius)  # the other turtles (nodes.traffic)
        self.set_params(params)
        self.costmap = Costmap(world.size)  # what the scans have seen that the world does not declare
        self.unknown: list[Circle] = []  # the costmap's circles after the latest scan
        self.scan_points = np.zeros((0, 2))  # world coordinates of the latest scan's hits, walls left out
        self.unknown_points = np.zeros((0, 2))  # those of them the declared obstacles do not explain
        self.scan_time = -math.inf

    def set_params(self, params: NavigatorParams) -> None:
        """Use ``params`` from now on: a new robot_radius or clearance at the next plan, a new
        scan_timeout at once."""
        self.params = params
        self.keep = params.robot_radius + params.clearance  # m the turtle keeps from every obstacle
        self.declared = inflate(self.world.obstacles, self.keep)

    def scan(self, scan: LaserScan, here: Pose | None, now: float) -> bool:
        """Take in a scan: its hits (walls left out) are what the turtle avoids until
        ``scan_timeout`` after ``now``; what the world does not declare among them goes into
        the costmap, whose beams also clear what is no longer there.  A scan that does not say
        where it was taken is placed at ``here``, the latest pose; without one it is ignored
        (False)."""
        origin = (scan.origin_x, scan.origin_y, scan.origin_theta)
        if not all(math.isfinite(v) for v in origin):
            if here is None:
                return False
            origin = (here.x, here.y, here.theta)
        angles = scan.angle_min + scan.angle_increment * np.arange(len(scan.ranges))
        points = hit_points(*origin, np.asarray(scan.ranges, dtype=float), angles)
        self.scan_points = off_walls(points, self.world.size)
        unknown = unexplained(self.scan_points, self.world.obstacles)
        self.unknown_points = unknown[~self.traffic.explains(unknown, now)]  # the others: nodes.traffic
        ranges = np.asarray(scan.ranges, dtype=float)
        self.costmap.update(*origin, ranges, scan.angle_min, scan.angle_increment, scan.range_max, self.unknown_points)
        self.unknown = self.costmap.circles()
        self.scan_time = now
        return True

    def scans_fresh(self, now: float) -> bool:
        """The latest scan is recent enough (``scan_timeout``) to avoid what it saw."""
        return now - self.scan_time <= self.params.scan_timeout

    def seen(self, now: float = -math.inf) -> list[Circle]:
        """What the scans have seen that the world does not declare, and the other turtles that
        stand still at ``now`` (nodes.traffic: a moving one is given way to, or gives way),
        grown by what the turtle keeps."""
        r = self.traffic.radius + self.keep
        others = [Circle(x, y, r) for x, y, speed in self.traffic.centres(now) if speed <= STANDING]
        return [Circle(c.x, c.y, c.r + self.keep) for c in self.unknown] + others

    def plan(self, pose: Pose, x: float, y: float, seen: list[Circle]) -> Path | None:
        """The shortest way from ``pose`` to (x, y) round the declared obstacles and ``seen``,
        through no gap between one of them and a wall too narrow for the turtle (unless the
        goal lies in it)."""
        seen = [part for c in seen for part in self._split_on(x, y, c)]
        circles = self.declared + seen
        plugs = wall_plugs(circles, self.world.size, self.params.robot_radius)
        circles += [c for c in plugs if containing(x, y, [c]) is None]
        return shortest_path((pose.x, pose.y), (x, y), escape(pose.x, pose.y, circles), self.world.size)

    def _split_on(self, x: float, y: float, seen: Circle) -> list[Circle]:
        """``seen`` (one of ``seen()``), or if (x, y) lies in it, one circle for each hit it
        covers: a circle covers its hits with room to spare (up to half a costmap square), which
        must not put a goal beyond the margin of everything seen inside the margin.  So a goal
        is walled in by what is seen exactly when a hit lies within ``keep`` of it."""
        if containing(x, y, [seen]) is None:
            return [seen]
        parts = []
        for hx, hy in self.costmap.within(seen.x, seen.y, seen.r - self.keep):
            r, d = HIT_PAD + self.keep, math.hypot(x - hx, y - hy)
            # a goal at least ``keep`` from a hit is outside its circle: the pad is not the margin
            parts.append(Circle(float(hx), float(hy), r if d < self.keep else min(r, d - 1e-6)))
        return parts

    def walled_in(self, pose: Pose, x: float, y: float) -> str:
        """Which of the turtle and the goal (x, y) the declared obstacles enclose, when no way
        joins them: the one that reaches fewer of the world's free corners (a pocket at a
        corner holds one; "the goal" if they reach as many)."""
        s = self.world.size
        corners = [
            (cx, cy) for cx, cy in ((0.0, 0.0), (s, 0.0), (0.0, s), (s, s)) if containing(cx, cy, self.declared) is None
        ]

        def reached(px: float, py: float) -> int:
            circles = escape(px, py, self.declared)
            return sum(shortest_path((px, py), c, circles, s) is not None for c in corners)

        return "the turtle" if reached(pose.x, pose.y) < reached(x, y) else "the goal"
