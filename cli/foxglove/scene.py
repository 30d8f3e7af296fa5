"""The ready-made 3D scene for Foxglove, from turtlectl's messages (pure: no Zenoh).

Foxglove's well-known schemas (the foxglove-sdk's ``foxglove.messages``, protobuf on the wire),
all in the frame ``world`` (m; the world's lower-left corner at the origin, z up):

* ``scene`` (SceneUpdate): the world's square and its declared obstacles (entity ``world``),
  the turtle as an arrow along its heading with its name above it (``turtle``), its trail
  (``trail``, the last ``TRAIL`` positions 5 cm apart or more), the current goal (``goal``: an
  arrow at the goal pose and the path the navigator follows to it, gone one second after the
  last feedback).  Every other turtle of ``turtles`` likewise, its entities named after it
  (``turtle/turtle2``, ``trail/turtle2``, ``goal/turtle2``: its goal from
  ``turtle2/navigate_to/feedback``), and deleted when it leaves ``turtles`` (killed);
* ``scene/scan`` (LaserScan): each scan placed at the pose it was taken from (its origin);
* ``log`` (Log): every node's log records (``turtlectl/log/<node>``), for Foxglove's Log panel.

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
    LogLevel,
    Point3,
    Pose,
    Quaternion,
    SceneEntity,
    SceneEntityDeletion,
    SceneEntityDeletionType,
    SceneUpdate,
    TextPrimitive,
    Timestamp,
    Vector3,
)
from foxglove.messages import Log as LogEntry

from turtlectl.messages import LaserScan as Scan
from turtlectl.messages import Log, NavigateToFeedback, Turtles
from turtlectl.messages import Pose as TurtlePose
from turtlectl.messages.angles import heading_radians
from turtlectl.messages.keys import FIRST_TURTLE
from turtlectl.messages.world import World
from turtlectl.sim.turtles import others

FRAME = "world"
SCENE = "scene"  # topic of the SceneUpdate channel
SCAN = "scene/scan"  # topic of the LaserScan channel
LOG = "log"  # topic of the Log channel: every node's log records (Foxglove's Log panel)
TRAIL = 2000  # positions kept in the trail
TRAIL_STEP = 0.05  # m between two trail positions
GOAL_LIFETIME = 1.0  # s the goal stays drawn after its last feedback

WALL = Color(r=0.8, g=0.8, b=0.8, a=1.0)
OBSTACLE = Color(r=0.85, g=0.3, b=0.25, a=0.9)
TURTLE = Color(r=0.2, g=0.7, b=0.3, a=1.0)
TRAIL_COLOUR = Color(r=0.3, g=0.6, b=1.0, a=0.8)
GOAL = Color(r=1.0, g=0.8, b=0.1, a=0.9)
LABEL = Color(r=1.0, g=1.0, b=1.0, a=1.0)
LABEL_SIZE = 14.0  # px: a turtle's name, the same size however far the camera is
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


def entity_id(kind: str, turtle: str = FIRST_TURTLE) -> str:
    """A turtle's entity of ``kind`` (turtle, trail, goal): turtle1's is ``kind`` alone, as
    before there were others; another's ``kind/<name>``."""
    return kind if turtle == FIRST_TURTLE else f"{kind}/{turtle}"


def turtle_entity(pose: TurtlePose, ns: int, name: str = FIRST_TURTLE) -> SceneEntity:
    """Turtle ``name``: an arrow 0.5 m long along its heading, its name above it."""
    return SceneEntity(
        timestamp=timestamp(ns),
        frame_id=FRAME,
        id=entity_id("turtle", name),
        texts=[
            TextPrimitive(
                pose=planar(pose.x, pose.y + 0.45, 0.0, 0.1),
                billboard=True,
                font_size=LABEL_SIZE,
                scale_invariant=True,
                color=LABEL,
                text=name,
            )
        ],
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


def goal_entity(feedback: NavigateToFeedback, ns: int, turtle: str = FIRST_TURTLE) -> SceneEntity:
    """``turtle``'s running goal: an arrow at its pose (theta in degrees on the wire), and the
    path the navigator follows to it (a line, when there is one)."""
    return SceneEntity(
        timestamp=timestamp(ns),
        frame_id=FRAME,
        id=entity_id("goal", turtle),
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
    """A turtle's recent positions, a point every ``TRAIL_STEP`` m."""

    def __init__(self, turtle: str = FIRST_TURTLE) -> None:
        self.turtle = turtle
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
            id=entity_id("trail", self.turtle),
            lines=[strip(self.points, 0.03, 0.01, TRAIL_COLOUR)],
        )


def update(*entities: SceneEntity, deleted: Iterable[str] = (), ns: int = 0) -> SceneUpdate:
    """``entities`` drawn (each replaces the one of its id), those of ids ``deleted`` removed."""
    deletions = [
        SceneEntityDeletion(timestamp=timestamp(ns), type=SceneEntityDeletionType.MatchingId, id=i) for i in deleted
    ]
    return SceneUpdate(deletions=deletions, entities=list(entities))


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


#: Python's (and ROS's) log levels, the least severe each starts at, as Foxglove numbers them
_LOG_LEVELS = (
    (50, LogLevel.Fatal),
    (40, LogLevel.Error),
    (30, LogLevel.Warning),
    (20, LogLevel.Info),
    (1, LogLevel.Debug),
)


def log_entry(record: Log) -> LogEntry:
    """A node's log record as Foxglove's Log: its level (DEBUG .. CRITICAL as Debug .. Fatal),
    the node as its name, its text, file and line, stamped when it was logged."""
    level = next((foxglove for least, foxglove in _LOG_LEVELS if record.level >= least), LogLevel.Unknown)
    return LogEntry(
        timestamp=timestamp(record.stamp),
        level=level,
        message=record.message,
        name=record.node,
        file=record.file,
        line=max(0, record.line),
    )


class SceneMaker:
    """What to draw for each message received: ``on_message`` returns (topic, Foxglove message)
    pairs for ``SCENE``, ``SCAN`` and ``LOG``; the world entity is ``world_update`` (send it again now
    and then: a viewer that connects later needs it, and the server keeps nothing)."""

    TURTLE_PERIOD = 0.05  # s: the turtle is redrawn at 20 Hz at most (poses come at 62.5 Hz)

    def __init__(self, world: World):
        self.world = world
        self.trail = Trail()
        self.others: dict[str, Trail] = {}  # the other turtles of the latest ``turtles``, by name
        self._turtles_seen = False  # a ``turtles`` message arrived: whose feedback is whose is known
        self._last_turtle = 0

    def world_update(self, ns: int) -> tuple[str, SceneUpdate]:
        trails = [t.entity(ns) for t in (self.trail, *self.others.values())]
        return SCENE, update(world_entity(self.world, ns), *trails)

    def goal_owner(self, key: str) -> str | None:
        """Whose navigator publishes feedback on ``key``: another turtle's when the chunk before
        ``navigate_to/feedback`` names one (``turtle2/...``, ``lab1/turtle2/...``), else turtle1's
        (``navigate_to/feedback``, a domain's ``lab1/navigate_to/feedback``); None when that chunk
        may name a turtle not known yet (no ``turtles`` message so far)."""
        parts = key.split("/")
        if len(parts) >= 3 and parts[-3] in self.others:
            return parts[-3]
        return FIRST_TURTLE if len(parts) < 3 or self._turtles_seen else None

    def _turtles(self, msg: Turtles, ns: int) -> SceneUpdate | None:
        """Every turtle but turtle1 (drawn from its pose) with its trail; those gone deleted
        (None: turtle1 alone)."""
        self._turtles_seen = True
        now = others(msg, but=FIRST_TURTLE)
        gone = self.others.keys() - {name for name, *_ in now}
        if not now and not gone:
            return None
        for name in gone:
            del self.others[name]
        drawn = []
        for name, x, y, theta in now:
            trail = self.others.setdefault(name, Trail(name))
            pose = TurtlePose(x=x, y=y, theta=theta)
            trail.add(pose)
            drawn += [turtle_entity(pose, ns, name), trail.entity(ns)]
        deleted = [entity_id(kind, name) for name in sorted(gone) for kind in ("turtle", "trail", "goal")]
        return update(*drawn, deleted=deleted, ns=ns)

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
            owner = self.goal_owner(key)
            return [] if owner is None else [(SCENE, update(goal_entity(msg, ns, owner)))]
        if isinstance(msg, Turtles):
            drawn = self._turtles(msg, ns)
            return [] if drawn is None else [(SCENE, drawn)]
        if isinstance(msg, Log):
            return [(LOG, log_entry(msg))]
        return []
