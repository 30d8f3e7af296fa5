"""The ROS 2 bridge's mapping table: which turtlectl key crosses to which ROS 2 topic, as which ROS
type, in which direction (pure: no DDS, no Zenoh; ``launch --check`` validates it without Cyclone).

An entry (``[[node.params.topics]]`` in a launch file)::

    key = "chatter"                 # the turtlectl key, as a node at the top level writes it
    ros = "/chatter"                # the ROS 2 topic (absolute)
    type = "std_msgs/msg/String"    # the ROS 2 type (one of ROS_TYPES)
    direction = "from_ros"          # to_ros, from_ros or both
    qos = "reliable"                # reliable (rclpy's default, 10) or sensor (best effort)

The turtlectl type on ``key`` follows from the ROS type (``ROS_TYPES``): ``std_msgs/msg/String`` is
turtlectl's ``String``, ``nav_msgs/msg/Odometry`` is made from a ``Pose``, and so on.  Any other ROS
type names a user's own flat message type (``my_msgs/msg/Reading`` is ``my_msgs/Reading``: found by
nodes.ros2_generic.user_type), which crosses both ways field for field (nodes.ros2_generic's rules).

The default table (``default_entries``) is per turtle: turtle1, outside a namespace, with the
single-turtle keys (``turtle1/cmd_vel``, ``turtle1/pose``, ``obstacles``, ``robot/status``), any
other turtle ``turtleN`` with its namespace's (``turtleN/obstacles``, ``turtleN/robot/status``);
the ROS topic is the key's resolved name with a leading slash (``/turtle2/robot/status``).
"""

from __future__ import annotations

from collections import deque
from typing import Annotated, Literal

import msgspec

from turtlectl.messages.codec import type_name
from turtlectl.messages.keys import CLOCK, CMD_VEL, FIRST_TURTLE, OBSTACLES, POSE, STATUS, TURTLES, resolve
from turtlectl.nodes import ros2_generic
from turtlectl.runtime.loader import suggestion

#: ROS 2 type -> (the turtlectl message type on the key, the directions it can cross).  The bridge's
#: conversions (nodes.ros2_mapping.TO_ROS / FROM_ROS) cover exactly these; a unit test keeps them equal.
ROS_TYPES: dict[str, tuple[str, tuple[str, ...]]] = {
    "geometry_msgs/msg/Twist": ("Twist", ("to_ros", "from_ros")),
    "turtlesim/msg/Pose": ("Pose", ("to_ros", "from_ros")),
    "nav_msgs/msg/Odometry": ("Pose", ("to_ros",)),
    "geometry_msgs/msg/Pose2D": ("Pose", ("to_ros",)),
    "sensor_msgs/msg/LaserScan": ("LaserScan", ("to_ros", "from_ros")),
    "capstone_msgs/msg/TurtleStatus": ("TurtleStatus", ("to_ros", "from_ros")),
    "rosgraph_msgs/msg/Clock": ("Clock", ("to_ros",)),
    "rcl_interfaces/msg/Log": ("Log", ("to_ros",)),
    "std_msgs/msg/String": ("String", ("to_ros", "from_ros")),
}

RosTopic = Annotated[str, msgspec.Meta(pattern=r"^/[A-Za-z_~{][A-Za-z0-9_/{}~]*$")]
Key = Annotated[str, msgspec.Meta(pattern=r"^/?[A-Za-z0-9_\-.~]+(/[A-Za-z0-9_\-.~*]+)*$")]  # a Zenoh key; * for a chunk


class BridgeTopic(msgspec.Struct, forbid_unknown_fields=True, frozen=True, kw_only=True):
    """One row of the bridge's table: turtlectl ``key`` <-> ROS 2 topic ``ros`` of ROS type ``type``."""

    key: Key  # -: the turtlectl key, as a node at the top level writes it (``chatter``, ``turtle2/pose``)
    ros: RosTopic  # -: the ROS 2 topic, absolute (``/chatter``)
    type: str  # -: the ROS 2 type, ``package/msg/Name`` (one the bridge converts, or a flat type of your own: see the how-to)
    direction: Literal["to_ros", "from_ros", "both"] = "to_ros"  # -: which way it crosses
    #: -: reliable (rclpy's 10), sensor (best effort, keep 5) or latched (reliable, transient local, keep 1000: /rosout's)
    qos: Literal["reliable", "sensor", "latched"] = "reliable"

    def __post_init__(self) -> None:
        known = ROS_TYPES.get(self.type)
        if known is None:
            user = ros2_generic.user_type(self.type)
            if user is None:
                names = ", ".join(sorted(ROS_TYPES))
                hint = suggestion(self.type, ROS_TYPES)
                raise ValueError(
                    f"unknown ROS type {self.type!r} for {self.ros}{hint} (the bridge converts: {names}, "
                    "and a message type of your own, package/msg/Name, declared in the module package)"
                )
            wrong = ros2_generic.field_that_cannot_cross(user)
            if wrong is not None:
                raise ValueError(
                    f"{type_name(user)} cannot cross to ROS 2 ({self.ros}): its field {wrong} has no ROS type "
                    "(bool, int, float, str, and lists or tuples of one of those cross)"
                )
            return
        ways = ("to_ros", "from_ros") if self.direction == "both" else (self.direction,)
        for way in ways:
            if way not in known[1]:
                raise ValueError(f"{self.type} crosses only {' and '.join(known[1])}, not {way} ({self.ros})")

    @property
    def message_type(self) -> str:
        """The turtlectl message type on ``key``: a built-in's class name in turtlectl.messages, a
        user's type's full name (``my_msgs/Reading``)."""
        known = ROS_TYPES.get(self.type)
        return known[0] if known is not None else str(ros2_generic.turtlectl_name(self.type))

    @property
    def generic(self) -> bool:
        """Whether the row's type is a user's own (crossing field for field), not a built-in's."""
        return self.type not in ROS_TYPES

    @property
    def to_ros(self) -> bool:
        return self.direction in ("to_ros", "both")

    @property
    def from_ros(self) -> bool:
        return self.direction in ("from_ros", "both")


def turtle_entries(turtle: str) -> list[BridgeTopic]:
    """The default rows of one turtle: turtle1 with the single-turtle keys, ``turtleN`` with its
    namespace's (messages.keys.resolve)."""
    ns = "" if turtle == FIRST_TURTLE else turtle

    def row(key: str, ros_key: str, ros_type: str, direction: str = "to_ros", qos: str = "reliable") -> BridgeTopic:
        return BridgeTopic(
            key=resolve(key, ns), ros="/" + resolve(ros_key, ns), type=ros_type, direction=direction, qos=qos
        )

    return [
        row(CMD_VEL, CMD_VEL, "geometry_msgs/msg/Twist", "both"),
        row(POSE, POSE, "turtlesim/msg/Pose"),
        row(POSE, f"{FIRST_TURTLE}/odom", "nav_msgs/msg/Odometry"),
        row(OBSTACLES, OBSTACLES, "sensor_msgs/msg/LaserScan"),
        row(STATUS, STATUS, "capstone_msgs/msg/TurtleStatus"),
    ]


#: the rows of the system as a whole (not per turtle): the simulated clock and the log stream
SYSTEM_ENTRIES = (
    BridgeTopic(key=CLOCK, ros="/clock", type="rosgraph_msgs/msg/Clock"),
    BridgeTopic(key="turtlectl/log/*", ros="/rosout", type="rcl_interfaces/msg/Log", qos="latched"),
)


def turtle_of_key(key: str) -> str:
    """The turtle a default row's key is about: ``turtle2`` for ``turtle2/robot/status``, turtle1 for
    the single-turtle keys (``obstacles``, ``robot/status``) -- the frame ids of its ROS messages."""
    head = key.split("/", 1)[0]
    return head if head.startswith("turtle") and head[6:].isdigit() else FIRST_TURTLE


def wanted_turtles(system: list[str], listed: list[str]) -> list[str]:
    """The turtles to bridge: ``listed`` (the ``turtles`` parameter) that the system has, in its
    order, or every one of ``system`` when none are listed."""
    return [t for t in system if not listed or t in listed]


def bridged_keys(rows: list[BridgeTopic], defaults: bool, turtles: list[str]) -> dict[str, tuple[str, ...]]:
    """The keys a bridge publishes and subscribes to (Interface fields): ``rows``' and, with
    ``defaults``, each listed turtle's default rows, every turtle's (``*/cmd_vel``) when none are
    listed, the system's rows and ``turtles``."""
    table = list(rows)
    publishes: list[str] = []
    subscribes: list[str] = []
    if defaults:
        table += SYSTEM_ENTRIES
        subscribes.append(TURTLES)
        for turtle in turtles or [FIRST_TURTLE]:
            table += turtle_entries(turtle)
        if not turtles:  # any turtle the simulator reports, spawned ones too
            publishes.append(f"*/{CMD_VEL.split('/', 1)[1]}")
            subscribes += [
                f"*/{CMD_VEL.split('/', 1)[1]}",
                f"*/{POSE.split('/', 1)[1]}",
                f"*/{OBSTACLES}",
                f"*/{STATUS}",
            ]
    for row in table:
        if row.from_ros:
            publishes.append(row.key)
        if row.to_ros:
            subscribes.append(row.key)
    return {"publishes": tuple(dict.fromkeys(publishes)), "subscribes": tuple(dict.fromkeys(subscribes))}


class OwnEcho:
    """What the bridge itself published on a turtlectl key, remembered so that the bridge's own
    subscription on the same key does not send it back to ROS (``cmd_vel`` both ways).  Pure:
    ``sent(msg)`` when publishing, ``is_own(msg)`` when one arrives (forgotten once seen)."""

    def __init__(self, keep: int = 64):
        self._sent: deque[object] = deque(maxlen=keep)

    def sent(self, msg: object) -> None:
        self._sent.append(msg)

    def is_own(self, msg: object) -> bool:
        try:
            self._sent.remove(msg)
        except ValueError:
            return False
        return True
