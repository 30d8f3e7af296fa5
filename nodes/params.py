"""Parameters of each node, with their defaults: the one source of truth; and what each
declares, its ``Claims`` and ``Interface`` (runtime.config), written once here, pure, so that the
node class carries them as a user's node class does and nodes.kinds reads them without
importing the node (tests/unit/nodes/test_kinds.py checks each against what the node declares).

The launch file's ``[node.params]`` tables are validated against these Structs
before anything starts (constraints carry the key path into the error); each
node process decodes its own table into them.
"""

from __future__ import annotations

import ipaddress
from typing import Annotated, ClassVar, Literal

import msgspec

from turtlectl.messages.keys import (
    CMD_VEL,
    GRAPH,
    MOVING,
    NAVIGATE_TO,
    OBSTACLES,
    POSE,
    RESET,
    ROS2_BRIDGE,
    STATUS,
    TURTLES,
)
from turtlectl.messages.units import LongTimeout, NonNegative, Percent, Positive, Rate, ShortTimeout
from turtlectl.messages.world import Obstacle
from turtlectl.nodes.control import Gains
from turtlectl.nodes.ros2_table import BridgeTopic, bridged_keys
from turtlectl.runtime.config import Claim, Interface

Degrees = Annotated[float, msgspec.Meta(ge=-360.0, le=360.0)]
PhantomRate = Annotated[float, msgspec.Meta(ge=0.0, le=100.0)]
Lifetime = Annotated[float, msgspec.Meta(ge=0.01, le=10.0)]
Circles = Annotated[list[Obstacle], msgspec.Meta(max_length=100)]
RosDomain = Annotated[int, msgspec.Meta(ge=-1, le=232)]
Rows = Annotated[list[BridgeTopic], msgspec.Meta(max_length=200)]


class NavigatorParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """The navigator: tolerances, the margin it keeps round obstacles, its safety net for what
    the scan sees ahead, and the limits that end a goal.  Paths go round every obstacle,
    declared or seen by the scan, at robot_radius + clearance from it; goals nearer an
    obstacle than that are refused.  Every field (``# unit: meaning``) can change at run time
    (``turtlectl param set``); robot_radius and clearance apply from the next plan."""

    position_tolerance: Positive = 0.01  # m: how near the goal's position counts as arrived
    heading_tolerance: Positive = 0.5  # degrees: how near the goal's heading counts as arrived
    robot_radius: Positive = 0.3  # m: the turtle's size (half its width); no obstacle may come nearer its centre
    clearance: NonNegative = 0.15  # m: kept from every obstacle beyond robot_radius when planning
    safety_distance: Positive = 0.4  # m: the turtle stops while an obstacle is this close in its direction of travel
    corridor_width: Positive = 0.6  # m: width of the corridor, centred on the path, that the safety check looks along
    obstacle_decel: Positive = 2.0  # m/s^2: braking used to slow down before an obstacle ahead
    scan_timeout: ShortTimeout = 1.0  # s: a scan older than this is forgotten (longer than the scan period)
    blocked_timeout: LongTimeout = 10.0  # s: blocked, or with no way round the scan's, before failing "blocked"
    goal_timeout: LongTimeout = 30.0  # s: before a goal fails with reason "timeout"
    pose_timeout: ShortTimeout = 0.5  # s: without a pose before a running goal fails "no pose" (poses come every 16 ms)
    min_battery: Percent = 5.0  # %: below it goals are refused with reason "battery low"
    feedback_rate: Rate = 10.0  # Hz: NavigateToFeedback replies to the caller of a goal
    gains: Gains = msgspec.field(default_factory=Gains)  # table: tuning of the control law


class StatusMonitorParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """The status monitor: the rate of ``robot/status`` and the simulated battery
    (``# unit: meaning`` per field)."""

    rate: Rate = 10.0  # Hz: of robot/status
    battery: Percent = 100.0  # %: the charge at start
    drain_per_second: NonNegative = 0.01  # %/s: drained always
    drain_per_metre: NonNegative = 0.1  # %/m: drained per metre travelled

    FIXED: ClassVar[dict[str, str]] = {"battery": "it is the charge at start (`turtlectl reset` fills the battery)"}


class ObstacleDetectorParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """The mock laser scanner: beams a tenth of a degree apart at most over a full turn
    (3600 beams take about 1 ms per scan), and phantom detections to stress the navigator
    (the mock sensor of docs/capstone.md): each phantom is a circle of phantom_radius,
    phantom_distance away in a random direction, seen for phantom_lifetime.
    undeclared_obstacles are circles the scan sees that the world does not declare: the
    navigator learns of them only by scanning and plans round them as it goes (the simulator
    does not collide with them).  ``# unit: meaning`` per field."""

    rate: Rate = 5.0  # Hz: of the scan
    beams: Annotated[int, msgspec.Meta(ge=1, le=3600)] = 72  # count: rays per scan
    angle_min: Degrees = -180.0  # degrees: first beam, relative to the heading (at most 360 below angle_max)
    angle_max: Degrees = 180.0  # degrees: last beam, relative to the heading (above angle_min)
    range_min: NonNegative = 0.0  # m: nearest range reported (below range_max)
    range_max: Positive = 10.0  # m: farthest range; beams that hit nothing report it
    phantom_rate: PhantomRate = 0.0  # 1/s: new phantoms per second on average (0: none)
    phantom_lifetime: Lifetime = 1.0  # s: how long each phantom is seen
    phantom_radius: Positive = 0.2  # m: radius of each phantom
    phantom_distance: Positive = 1.5  # m: how far from the turtle a phantom appears
    phantom_seed: int = 0  # -: seed of the phantoms' random sequence (repeatable runs)
    undeclared_obstacles: Circles = msgspec.field(default_factory=list)  # m: circles (x, y, radius) only the scan sees

    FIXED: ClassVar[dict[str, str]] = {"phantom_seed": "it seeds the phantoms' random sequence once, at start"}

    def __post_init__(self) -> None:
        if not self.angle_min < self.angle_max <= self.angle_min + 360.0:
            raise ValueError("angle_max must be above angle_min and at most 360 degrees from it")
        if not self.range_min < self.range_max:
            raise ValueError("range_min must be below range_max")


class Ros2BridgeParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """The ROS 2 bridge: puts the system into a ROS 2 graph over DDS (Eclipse Cyclone DDS, the
    ``ros2`` extra), on ``address`` only.  The default table (docs/how-to/ros2.md) bridges each
    turtle's cmd_vel (both ways), pose (turtlesim Pose and nav_msgs Odometry), scan and status, the
    simulated clock and the log stream; ``topics`` adds rows (``[[node.params.topics]]``: key, ros,
    type, direction, qos).  ``# unit: meaning`` per field."""

    ros_domain: RosDomain = -1  # id: the ROS 2 domain (-1: ROS_DOMAIN_ID, else 0)
    address: str = "127.0.0.1"  # IPv4: the only address DDS discovery and data use (loopback unless told otherwise)
    turtles: list[str] = msgspec.field(default_factory=list)  # names: the turtles to bridge (empty: every one)
    defaults: bool = True  # flag: bridge the default table (each turtle's topics, clock, log) besides topics
    topics: Rows = msgspec.field(default_factory=list)  # table: more rows (key, ros, type, direction, qos)

    FIXED: ClassVar[dict[str, str]] = {
        "ros_domain": "the DDS participant joins its domain once, at start",
        "address": "the DDS participant is configured once, at start",
        "topics": "the DDS readers and writers are made at start",
        "defaults": "the DDS readers and writers are made at start",
        "turtles": "the DDS readers and writers are made at start",
    }

    def narrow_interface(self, declared: Interface) -> Interface:
        """What a bridge with these parameters does (its table's keys), within ``declared``: under
        ``launch --secure`` its router allows that and nothing else."""
        return msgspec.structs.replace(declared, **bridged_keys(self.topics, self.defaults, self.turtles))


Port = Annotated[int, msgspec.Meta(ge=1, le=65535)]
Role = Literal["viewer", "operator", "teleop"]


class WebParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """The web page (``turtlectl web``): the world, goals by pointing, the keyboard and the live panels
    in a browser, served on ``host``:``port`` (loopback unless told otherwise).  On a ``launch
    --secure`` system the page does what ``role``'s login may, no more.  ``# unit: meaning`` per field."""

    host: str = "127.0.0.1"  # address: where the page listens (loopback unless told; 0.0.0.0: every one)
    port: Port = 8080  # TCP port: the page's, http://host:port/
    role: Role = "operator"  # login: the role the page uses on a --secure system (viewer, operator, teleop)
    trail: Annotated[int, msgspec.Meta(ge=0, le=100000)] = 2000  # poses: each turtle's trail drawn on the page
    insecure: bool = False  # flag: may listen beyond loopback (the page has no logins of its own)

    FIXED: ClassVar[dict[str, str]] = {
        "host": "the page's socket is bound once, at start",
        "port": "the page's socket is bound once, at start",
        "role": "the page logs in once, at start",
        "trail": "a page reads it when it connects",
        "insecure": "the page's socket is bound once, at start",
    }

    def __post_init__(self) -> None:
        try:
            address = ipaddress.ip_address(self.host.strip("[]"))
        except ValueError:
            raise ValueError(f"host {self.host!r} is not an IP address") from None
        if not (address.is_loopback or self.insecure):
            raise ValueError(
                f"host {self.host} reaches beyond this machine, and the page has no logins of its own: anyone who"
                f" reaches it can do what its role ({self.role}) may; set insecure = true (turtlectl web --insecure)"
                " to serve it so on a network you trust"
            )


NAVIGATOR_CLAIMS = (Claim("srv", NAVIGATE_TO),)
NAVIGATOR_INTERFACE = Interface(
    publishes=(CMD_VEL,),
    subscribes=(POSE, STATUS, OBSTACLES, f"/{TURTLES}"),
    serves=(MOVING,),  # the simulator about to move the turtle: the running goal ends
    goals=(NAVIGATE_TO,),  # navigate_to, its cancel, its feedback, its callers' tokens
)
STATUS_MONITOR_CLAIMS = (Claim("pub", STATUS),)
STATUS_MONITOR_INTERFACE = Interface(publishes=(STATUS,), subscribes=(POSE,), serves=(f"/{RESET}",))
OBSTACLE_DETECTOR_CLAIMS = (Claim("pub", OBSTACLES),)
OBSTACLE_DETECTOR_INTERFACE = Interface(publishes=(OBSTACLES,), subscribes=(POSE, f"/{TURTLES}"))
#: one bridge per system: a second one's DDS side would bring back into the system what the first
#: sends to ROS, and the first send it to ROS again, without end
ROS2_BRIDGE_CLAIMS = (Claim("srv", f"/{ROS2_BRIDGE}"),)
#: the bridge carries what its table says, which a launch file extends: any key, both ways; it
#: follows the nodes' presence (their names in the ROS graph), and serves its claim
ROS2_BRIDGE_INTERFACE = Interface(publishes=("**",), subscribes=("**",), watches=(GRAPH,), serves=(f"/{ROS2_BRIDGE}",))
#: the page talks to the system through a client session of its own, logged in with its role (its rights
#: are the role's: runtime.roles); its node session only answers what every node answers
WEB_INTERFACE = Interface()
