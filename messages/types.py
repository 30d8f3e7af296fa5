"""The wire contract: every message that crosses a process boundary.

Rules (the reference for clients is docs/interfaces.md, generated from here):

* every Struct is strict (``forbid_unknown_fields``), keyword-only and frozen;
* every Struct names its wire tag explicitly (``class Pose(Message, tag="Pose")``), and
  the tag on the wire is the type's full name, its package's and its own
  (``"type": "turtlectl/Pose"`` in the encoded map: messages.naming), so a payload names its
  own type and renaming a class never changes it;
* fields added later get defaults, so old senders stay valid.

Units are SI unless a field says otherwise: metres, seconds, radians, except
where people read and type them, in degrees (``TurtleStatus.theta``,
``NavigateToRequest.theta``).  ``stamp`` is the publisher's time in nanoseconds
since the Unix epoch (the wall clock, or the simulated clock for a node with
``use_sim_time``), ``seq`` a per-publisher counter starting at 0.
"""

from __future__ import annotations

import enum
import math
from typing import Any

import msgspec

from turtlectl.messages.naming import REBUILT, full_name


class _Named(msgspec.StructMeta):
    """Gives every subclass of Message its full name as its msgspec tag (messages.naming):
    ``tag="Pose"`` declared in ``turtlectl.messages`` is ``turtlectl/Pose`` on the wire."""

    def __new__(mcls, name: str, bases: tuple[type, ...], namespace: dict[str, Any], **kwargs: Any) -> Any:
        if any(isinstance(base, _Named) for base in bases) and not namespace.get(REBUILT):
            kwargs["tag"] = full_name(str(kwargs.get("tag", name)), str(namespace.get("__module__", "")))
        return super().__new__(mcls, name, bases, namespace, **kwargs)


class Message(
    msgspec.Struct, metaclass=_Named, forbid_unknown_fields=True, kw_only=True, frozen=True, tag_field="type"
):
    """Base of every wire type: frozen (build a new one with ``msgspec.structs.replace``), and
    each subclass names its wire tag explicitly (``class Pose(Message, tag="Pose")``), so that
    renaming a class can never change the wire format.  The tag becomes the type's full name,
    ``package/Name``: the package is where the class is declared (its top-level module, or a
    script's file stem) unless the tag names one (``tag="capstone_interfaces/TurtleStatus"``)."""


class Twist(Message, tag="Twist"):
    """Velocity command for the turtle (turtlesim's ``cmd_vel``).

    linear: forward speed along the heading, m/s (negative drives backwards).
    angular: yaw rate, rad/s, counter-clockwise positive.
    """

    linear: float = 0.0
    angular: float = 0.0
    stamp: int = 0
    seq: int = 0


class Pose(Message, tag="Pose"):
    """The turtle's pose as turtlesim publishes it.

    x, y: position in the world frame, m (origin at the lower-left corner).
    theta: heading, rad, in [-pi, pi), 0 along +x, counter-clockwise positive.
    linear_velocity: m/s along the heading; angular_velocity: rad/s.
    contact: the turtle touches a declared obstacle or another turtle (it stops there, as at a wall).
    """

    x: float
    y: float
    theta: float
    linear_velocity: float = 0.0
    angular_velocity: float = 0.0
    contact: bool = False
    stamp: int = 0
    seq: int = 0


class TurtleStatus(Message, tag="TurtleStatus"):
    """The aggregated robot status of the capstone specification (docs/capstone.md), 10 Hz.

    x, y: position, m.  theta: heading in degrees, [0, 360).
    vel_x, vel_y: velocity in the world frame, m/s.
    battery: simulated charge, percent, [0, 100].
    """

    x: float
    y: float
    theta: float
    vel_x: float
    vel_y: float
    battery: float
    stamp: int = 0
    seq: int = 0


class LaserScan(Message, tag="LaserScan"):
    """A planar scan, as ``sensor_msgs/LaserScan`` (simplified).

    Angles are rad in the turtle's frame (0 = straight ahead, CCW positive);
    beam i points at ``angle_min + i * angle_increment``.  ranges are m;
    a beam that hits nothing within ``range_max`` reads ``inf`` (REP 117;
    ``"Infinity"`` in JSON, which has no infinity: ``echo --json``, recordings, Foxglove).
    origin_x, origin_y, origin_theta: the sensor's pose in the world when the
    scan was taken (m, m, rad), NaN if unknown; a moving reader needs it to
    place the hits (ROS would use tf for this).
    """

    angle_min: float
    angle_max: float
    angle_increment: float
    range_min: float
    range_max: float
    ranges: list[float]
    origin_x: float = math.nan
    origin_y: float = math.nan
    origin_theta: float = math.nan
    stamp: int = 0
    seq: int = 0


class NavigateToRequest(Message, tag="NavigateToRequest"):
    """Goal for the ``navigate_to`` service.

    x, y: goal position in the world frame, m.  theta: goal heading, degrees
    (any finite value; it is reduced modulo 360 exactly, in degrees).
    client: optional liveliness key of the caller (``@turtlectl/client/...``);
        if that token disappears while the goal runs, the goal is canceled.
    """

    x: float
    y: float
    theta: float
    client: str = ""


class GoalState(enum.StrEnum):
    """What the turtle does for a running goal (``NavigateToFeedback.state``); on the wire,
    the value: ``"turning"`` (in place, or on the way with too large a heading error to drive),
    ``"driving"`` (moving towards the goal position), ``"blocked"`` (something within the
    safety distance ahead: it only turns, and looks for another way), ``"replanning"``
    (no way round what the scan sees: stopped, it plans again with each scan)."""

    TURNING = "turning"
    DRIVING = "driving"
    BLOCKED = "blocked"
    REPLANNING = "replanning"


class NavigateToFeedback(Message, tag="NavigateToFeedback"):
    """Progress of a running goal, replied to its caller about 10 times a second.

    Also published on ``navigate_to/feedback`` for observers (``turtlectl view``).
    state: a GoalState, "turning", "driving" or "blocked".  distance_remaining: m.
    heading_remaining: degrees.  eta: estimated s to arrival.  elapsed: s.
    x, y, theta: current pose (m, m, degrees [0, 360)).
    goal_x, goal_y, goal_theta: the goal (m, m, degrees [0, 360)).
    scan_stale: no scan newer than the navigator's scan_timeout: it avoids only the
        declared obstacles of the world.
    path: the way the turtle follows, as points (x, y) in m from where it was planned to
        the goal (a straight way is its two ends; arcs round obstacles a point every 10
        degrees); empty while there is none (state "replanning").
    replans: how many times the path was planned again during this goal (something the
        scan sees in the way, or the turtle off its path).
    distance_remaining is measured along the path.
    """

    state: GoalState
    distance_remaining: float
    heading_remaining: float
    eta: float
    elapsed: float
    x: float
    y: float
    theta: float
    goal_x: float = 0.0
    goal_y: float = 0.0
    goal_theta: float = 0.0
    scan_stale: bool = False
    path: list[tuple[float, float]] = msgspec.field(default_factory=list)
    replans: int = 0
    stamp: int = 0
    seq: int = 0


class NavigateToResponse(Message, tag="NavigateToResponse"):
    """Outcome of a ``navigate_to`` goal.

    success: the goal was reached within tolerance.
    time_taken: seconds from the navigator receiving the request to the reply.
    reason: empty on success, otherwise why the goal was not reached: one of
        ``"blocked"``, ``"timeout"``, ``"canceled"``, ``"preempted"``, ``"caller gone"``,
        ``"no pose"``, ``"teleported"``, ``"reset"``, ``"navigator shut down"``,
        ``"battery low"``, ``"invalid goal"`` or ``"unreachable"`` (refusals; ``detail`` says why).
    position_error: final distance to the goal position, m.
    heading_error: final absolute heading error, degrees.
    x, y, theta: final pose (m, m, degrees [0, 360)).
    refused: the goal never started (invalid, unreachable, battery low); the pose is where the turtle is.
    detail: a sentence for people saying why, and what to do next (empty on success).
    """

    success: bool
    time_taken: float
    reason: str = ""
    refused: bool = False
    position_error: float = 0.0
    heading_error: float = 0.0
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    detail: str = ""


class Cancel(Message, tag="Cancel"):
    """Request to ``navigate_to/cancel``: stop the running goal.

    reason: what its caller is told (default "canceled"; teleop sends "teleop").
    detail: a sentence for people the caller is told with it (empty: the goal server's own).
    """

    reason: str = ""
    detail: str = ""


class TeleportAbsolute(Message, tag="TeleportAbsolute"):
    """Request to ``turtle1/teleport_absolute``, as turtlesim's: x, y in m, theta in rad."""

    x: float
    y: float
    theta: float


class Moving(Message, tag="Moving"):
    """Request to ``turtle1/moving``, from the simulator before it puts the turtle elsewhere; it
    moves the turtle once every server has answered (an ``Ack``).  Whatever drives the turtle
    serves it and stops first: the navigator ends its running goal with ``reason``, so it never
    drives on from a pose that no longer holds.

    reason: why the turtle moves: "teleported" or "reset".
    """

    reason: str = ""


class Reset(Message, tag="Reset"):
    """Request to ``reset``, as turtlesim's: turtle1 back at its spawn pose (made again if it
    was killed), every other turtle removed, the battery full."""


class SpawnRequest(Message, tag="SpawnRequest"):
    """Request to ``spawn``, as turtlesim's: a new turtle at x, y (m) facing theta (rad), named
    ``name`` (empty: the first free ``turtleN``).  Its keys are under its name:
    ``<name>/cmd_vel``, ``<name>/pose``, ``<name>/teleport_absolute``."""

    x: float
    y: float
    theta: float
    name: str = ""


class SpawnResponse(Message, tag="SpawnResponse"):
    """Answer of ``spawn``: the new turtle's name."""

    name: str


class Turtles(Message, tag="Turtles"):
    """Every turtle in the world, as the simulator publishes them on ``turtles`` (every 4th
    step: 15.6 Hz): ``names[i]`` is at ``x[i]``, ``y[i]`` (m) facing ``theta[i]`` (rad).  Each is
    solid to the others (``World.turtle_radius``) and seen by their scans."""

    names: list[str]
    x: list[float]
    y: list[float]
    theta: list[float]
    stamp: int = 0
    seq: int = 0


class Clock(Message, tag="Clock"):
    """The simulated time, as the simulator publishes it on ``clock`` after every step (ROS's
    ``/clock``).  ``clock``: ns since the Unix epoch, starting at the wall-clock time the simulator
    started and running ``real_time_factor`` times as fast as the wall clock (exactly one step,
    16 ms, per step).  A node started with ``use_sim_time`` runs its timers, timeouts and stamps
    on it."""

    clock: int
    real_time_factor: float = 1.0
    stamp: int = 0
    seq: int = 0


class Kill(Message, tag="Kill"):
    """Request to ``kill``, as turtlesim's: remove the turtle ``name`` (its keys go with it)."""

    name: str


class Ack(Message, tag="Ack"):
    """Answer of a simple service: ok, and a sentence saying what was done."""

    ok: bool = True
    detail: str = ""


class ErrorReply(Message, tag="ErrorReply"):
    """What a service sends back when it cannot even parse a request."""

    error: str


class SetParameter(Message, tag="SetParameter"):
    """Request to ``turtlectl/params/<node>/set``: change one parameter of a running node.

    name: the parameter, dotted into a table (``gains.lookahead``).
    value: its new value, as the launch file would hold it (a number, text, list or table).
    """

    name: str
    value: Any = None


class ParameterEvent(Message, tag="ParameterEvent"):
    """Published on ``turtlectl/parameter_events`` by a node each time one of its parameters
    changes at run time (``turtlectl param set``), as ROS 2's ``/parameter_events``.

    node: the node's name; name: the parameter (dotted); old_value, new_value: before and after.
    """

    node: str
    name: str
    old_value: Any = None
    new_value: Any = None
    stamp: int = 0
    seq: int = 0


class SetLogLevel(Message, tag="SetLogLevel"):
    """Request to ``turtlectl/nodes/<node>/log_level``: the level of the node's log from now on
    (DEBUG, INFO, WARNING or ERROR)."""

    level: str


class Log(Message, tag="Log"):
    """One record of a node's log, as every node publishes each on ``turtlectl/log/<node>``
    (ROS's ``/rosout`` and ``rcl_interfaces/Log``); ``turtlectl log`` reads them.

    level: Python's: 10 DEBUG, 20 INFO, 30 WARNING, 40 ERROR, 50 CRITICAL (ROS's DEBUG 10 ..
    FATAL 50).  node: the node's full name (``turtle2/navigator``).  message: the text, with its
    traceback if it has one.  file, function, line: where in the source it was logged.
    stamp: when it was logged (wall clock, ns).  seq: per node, from 0.
    """

    level: int
    node: str
    message: str
    file: str = ""
    function: str = ""
    line: int = 0
    stamp: int = 0
    seq: int = 0


class String(Message, tag="String"):
    """A line of text, as ROS 2's ``std_msgs/msg/String``: what the ROS 2 bridge publishes for one
    that crosses from ROS (``turtlectl echo chatter`` shows an rclpy talker's), and sends as one.

    data: the text.
    """

    data: str = ""
    stamp: int = 0
    seq: int = 0


ALL_TYPES: tuple[type[Message], ...] = (
    Twist,
    Pose,
    TurtleStatus,
    LaserScan,
    NavigateToRequest,
    NavigateToFeedback,
    NavigateToResponse,
    Cancel,
    Moving,
    TeleportAbsolute,
    Reset,
    SpawnRequest,
    SpawnResponse,
    Turtles,
    Clock,
    Kill,
    Ack,
    ErrorReply,
    SetParameter,
    ParameterEvent,
    SetLogLevel,
    Log,
    String,
)
