"""Parameters of each node, with their defaults: the one source of truth.

The launch file's ``[node.params]`` tables are validated against these Structs
before anything starts (constraints carry the key path into the error); each
node process decodes its own table into them.
"""

from __future__ import annotations

from typing import Annotated

import msgspec

from messages.units import LongTimeout, NonNegative, Percent, Positive, Rate, ShortTimeout
from messages.world import Obstacle
from nodes.control import Gains

Degrees = Annotated[float, msgspec.Meta(ge=-360.0, le=360.0)]


class NavigatorParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """position_tolerance: m.  heading_tolerance: degrees.
    robot_radius: m, the turtle's size (half its width): no obstacle may come nearer its
    centre.  clearance: m the planner keeps beyond robot_radius; paths go round every
    obstacle, declared or seen by the scan, at robot_radius + clearance from it, and goals
    nearer an obstacle than that are refused.
    safety_distance: m; the turtle stops while an obstacle is this close in its
    direction of travel (inside a corridor of corridor_width m, centred on its
    path), and slows down before, braking at obstacle_decel m/s^2; a scan older
    than scan_timeout s is forgotten (0.05 to 60 s, and longer than the scan period).
    blocked_timeout: s blocked, or with no way round what the scan sees, before the goal
    fails with reason "blocked" (0.1 to 3600).
    goal_timeout: s before a goal fails with reason "timeout" (0.1 to 3600).
    pose_timeout: s without a pose before a running goal fails with reason "no pose"
    (0.05 to 60; poses come every 16 ms).
    min_battery: %; below it goals are refused with reason "battery low".
    feedback_rate: Hz of NavigateToFeedback replies to the caller of a goal (0.1 to 100).
    """

    position_tolerance: Positive = 0.01
    heading_tolerance: Positive = 0.5
    robot_radius: Positive = 0.3
    clearance: NonNegative = 0.15
    safety_distance: Positive = 0.4
    corridor_width: Positive = 0.6
    obstacle_decel: Positive = 2.0
    scan_timeout: ShortTimeout = 1.0
    blocked_timeout: LongTimeout = 10.0
    goal_timeout: LongTimeout = 30.0
    pose_timeout: ShortTimeout = 0.5
    min_battery: Percent = 5.0
    feedback_rate: Rate = 10.0
    gains: Gains = msgspec.field(default_factory=Gains)


class StatusMonitorParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """rate: Hz of robot/status (0.1 to 100).  battery: starting charge, %.
    drain_per_second: %/s always; drain_per_metre: %/m travelled.
    """

    rate: Rate = 10.0
    battery: Percent = 100.0
    drain_per_second: NonNegative = 0.01
    drain_per_metre: NonNegative = 0.1


class ObstacleDetectorParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """rate: Hz of the scan (0.1 to 100).  beams: number of rays (1 to 3600, a tenth of a
    degree apart over a full turn; 3600 beams take about 1 ms per scan).  angle_min,
    angle_max: degrees relative to the heading (at most 360 apart).  range_min, range_max: m.
    Phantom detections, to stress the navigator (the mock sensor of docs/capstone.md):
    phantom_rate: new phantoms per s on average (0: none, at most 100); each is a circle of
    phantom_radius m, phantom_distance m away in a random direction, seen for
    phantom_lifetime s (0.01 to 10); phantom_seed makes the sequence repeatable.
    undeclared_obstacles: circles (x, y, radius in m) the scan sees that the world does not
    declare: the navigator learns of them only by scanning and plans round them as it goes
    (at most 100; the simulator does not collide with them).
    """

    rate: Rate = 5.0
    beams: Annotated[int, msgspec.Meta(ge=1, le=3600)] = 72
    angle_min: Degrees = -180.0
    angle_max: Degrees = 180.0
    range_min: NonNegative = 0.0
    range_max: Positive = 10.0
    phantom_rate: Annotated[float, msgspec.Meta(ge=0.0, le=100.0)] = 0.0
    phantom_lifetime: Annotated[float, msgspec.Meta(ge=0.01, le=10.0)] = 1.0
    phantom_radius: Positive = 0.2
    phantom_distance: Positive = 1.5
    phantom_seed: int = 0
    undeclared_obstacles: Annotated[list[Obstacle], msgspec.Meta(max_length=100)] = msgspec.field(default_factory=list)

    def __post_init__(self) -> None:
        if not self.angle_min < self.angle_max <= self.angle_min + 360.0:
            raise ValueError("angle_max must be above angle_min and at most 360 degrees from it")
        if not self.range_min < self.range_max:
            raise ValueError("range_min must be below range_max")
