"""The ready-made 3D scene for Foxglove, from turtlectl's messages (pure: no Zenoh).

Foxglove's well-known schemas (the foxglove-sdk's ``foxglove.messages``, protobuf on the wire),
all in the frame ``world`` (m; the world's lower-left corner at the origin, z up):

* ``scene`` (SceneUpdate): the world's square and its declared obstacles (entity ``world``),
  the turtle as an arrow along its heading (``turtle``), its trail (``trail``, the last
  ``TRAIL`` positions 5 cm apart or more), the current goal (``goal``: an arrow at the goal
  pose and the path the navigator follows to it, gone one second after the last feedback);
* ``scene/scan`` (LaserScan): each scan placed at the pose it was taken from (its origin).

The foxglove package is imported here, and this module only by the commands that draw.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterable

from foxglove.messages import (
    ArrowPrimitive,
    Color,
    CylinderPrimitive,
    Duration,
    LaserScan,
    LinePrimitive,
    LinePrimitiveLineType,
    Point3,
    Pose,
    Quaternion,
    SceneEntity,
    SceneUpdate,
    Timestamp,
    Vector3,
)

from turtlectl.messages import LaserScan as Scan
from turtlectl.messages import NavigateToFeedback
from turtlectl.messages import Pose as TurtlePose
from turtlectl.messages.angles import heading_radians
from turtlectl.messages.world import World

FRAME = "world"
SCENE = "scene"  # topic of the SceneUpdate channel
SCAN = "scene/scan"  # topic of the LaserScan channel
TRAIL = 2000  # positions kept in the trail
TRAIL_STEP = 0.05  # m between two trail positions
GOAL_LIFETIME = 1.0  # s the goal stays drawn after its last feedback

WALL = Color(r=0.8, g=0.8, b=0.8, a=1.0)
OBSTACLE = Color(r=0.85, g=0.3, b=0.25, a=0.9)
TURTLE = Color(r=0.2, g=0.7, b=0.3, a=1.0)
TRAIL_COLOUR = Color(r=0.3, g=0.6, b=1.0, a=0.8)
GOAL = Color(r=1.0, g=0.8, b=0.1, a=0.9)
OBSTACLE_HEIGHT = 0.3  # m: obstacles are drawn as cylinders this tall


def timestamp(ns: int) -> Timestamp:
    return Timestamp(ns // 1_000_000_000, ns % 1_000_000_000)


def planar(x: float, y: float, yaw: float, z: float = 0.0) -> Pose:
    """A pose at (x, y, z) m turned ``yaw`` rad about z (counter-clockwise from +x)."""
    return Pose(
        position=Vector3(x=x, y=y, z=z),
        orientation=Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2)),
    )


def strip(points: Iterable[tuple[float, float]], thickness: float, z: float, colour: Color) -> LinePrimitive:
    """A line through ``points`` (x, y in m) at height ``z`` m, ``thickness`` m wide."""
    return LinePrimitive(
        type=LinePrimitiveLineType.LineStrip,
        thickness=thickness,
        points=[Point3(x=x, y=y, z=z) for x, y in points],
        color=colour,
    )


def world_entity(world: World, ns: int) -> SceneEntity:
    """The square (a line loop at z = 0) and each obstacle (a cylinder of its radius)."""
    s = world.size
    corners = [Point3(x=x, y=y, z=0.0) for x, y in ((0, 0), (s, 0), (s, s), (0, s))]
    return SceneEntity(
        timestamp=timestamp(ns),
        frame_id=FRAME,
        id="world",
        lines=[LinePrimitive(type=LinePrimitiveLineType.LineLoop, thickness=0.05, points=corners, color=WALL)],
        cylinders=[
            CylinderPrimitive(
                pose=planar(o.x, o.y, 0.0, OBSTACLE_HEIGHT / 2),
                size=Vector3(x=2 * o.radius, y=2 * o.radius, z=OBSTACLE_HEIGHT),
                bottom_scale=1.0,
                top_scale=1.0,
                color=OBSTACLE,
            )
            for o in world.obstacles
        ],
    )


def turtle_entity(pose: TurtlePose, ns: int) -> SceneEntity:
    """The turtle: an arrow 0.5 m long along its heading."""
    return SceneEntity(
        timestamp=timestamp(ns),
        frame_id=FRAME,
        id="turtle",
        arrows=[
            ArrowPrimitive(
                pose=planar(pose.x, pose.y, pose.theta, 0.05),
                shaft_length=0.35,
                shaft_diameter=0.12,
                head_length=0.15,
                head_diameter=0.3,
                color=TURTLE,
            )
        ],
    )


def goal_entity(feedback: NavigateToFeedback, ns: int) -> SceneEntity:
    """The running goal: an arrow at its pose (theta in degrees on the wire), and the path
    the navigator follows to it (a line, when there is one)."""
    return SceneEntity(
        timestamp=timestamp(ns),
        frame_id=FRAME,
        id="goal",
        lifetime=Duration(int(GOAL_LIFETIME), 0),
        arrows=[
            ArrowPrimitive(
                pose=planar(feedback.goal_x, feedback.goal_y, heading_radians(feedback.goal_theta), 0.02),
                shaft_length=0.3,
                shaft_diameter=0.06,
                head_length=0.12,
                head_diameter=0.18,
                color=GOAL,
            )
        ],
        lines=[strip(feedback.path, 0.04, 0.015, GOAL)] if len(feedback.path) >= 2 else [],
    )


class Trail:
    """The turtle's recent positions, a point every ``TRAIL_STEP`` m."""

    def __init__(self) -> None:
        self.points: deque[tuple[float, float]] = deque(maxlen=TRAIL)

    def add(self, pose: TurtlePose) -> bool:
        """Keep ``pose``'s position if it moved far enough; whether the trail changed."""
        if self.points and math.dist(self.points[-1], (pose.x, pose.y)) < TRAIL_STEP:
            return False
        self.points.append((pose.x, pose.y))
        return True

    def clear(self) -> None:
        self.points.clear()

    def entity(self, ns: int) -> SceneEntity:
        return SceneEntity(
            timestamp=timestamp(ns),
            frame_id=FRAME,
            id="trail",
            lines=[strip(self.points, 0.03, 0.01, TRAIL_COLOUR)],
        )


def update(*entities: SceneEntity) -> SceneUpdate:
    return SceneUpdate(entities=list(entities))


def scan(msg: Scan, ns: int) -> LaserScan | None:
    """The scan placed at the pose it was taken from (None if that pose is unknown: NaN)."""
    if math.isnan(msg.origin_x) or math.isnan(msg.origin_y) or math.isnan(msg.origin_theta):
        return None
    return LaserScan(
        timestamp=timestamp(msg.stamp or ns),
        frame_id=FRAME,
        pose=planar(msg.origin_x, msg.origin_y, msg.origin_theta, 0.1),
        start_angle=msg.angle_min,
        end_angle=msg.angle_max,
        ranges=list(msg.ranges),
        intensities=[],
    )


class SceneMaker:
    """What to draw for each message received: ``on_message`` returns (topic, Foxglove message)
    pairs for ``SCENE`` and ``SCAN``; the world entity is ``world_update`` (send it again now
    and then: a viewer that connects later needs it, and the server keeps nothing)."""

    TURTLE_PERIOD = 0.05  # s: the turtle is redrawn at 20 Hz at most (poses come at 62.5 Hz)

    def __init__(self, world: World):
        self.world = world
        self.trail = Trail()
        self._last_turtle = 0

    def world_update(self, ns: int) -> tuple[str, SceneUpdate]:
        return SCENE, update(world_entity(self.world, ns), self.trail.entity(ns))

    def on_message(self, key: str, msg: object, ns: int) -> list[tuple[str, object]]:
        """``msg`` received on ``key`` at ``ns`` (ns since the epoch); keys are matched by their
        last part, so a system in a domain (``lab1/turtle1/pose``) is drawn too."""
        if isinstance(msg, TurtlePose) and key.endswith("turtle1/pose"):
            moved = self.trail.add(msg)
            if ns - self._last_turtle < self.TURTLE_PERIOD * 1e9 and not moved:
                return []
            self._last_turtle = ns
            return [(SCENE, update(turtle_entity(msg, ns), self.trail.entity(ns)))]
        if isinstance(msg, Scan):
            placed = scan(msg, ns)
            return [] if placed is None else [(SCAN, placed)]
        if isinstance(msg, NavigateToFeedback):
            return [(SCENE, update(goal_entity(msg, ns)))]
        return []
