"""Key expressions: which message type travels on which key.

Topics are plain keys (no leading slash, as Zenoh wants).  Liveliness tokens
live under ``@turtlectl/...`` (nodes: ``@turtlectl/node/<name>/<pid>/<host>/<start_ns>``)
so that ``*`` and ``**`` on the data space never match them: Zenoh never matches a
chunk that starts with ``@`` by a wildcard.

A system started with ``--domain D`` runs in a Zenoh namespace: every key above,
tokens included, is ``D/<key>`` on the router (``D/@turtlectl/node/...``).
"""

from __future__ import annotations

import re
from collections.abc import Collection, Mapping

import msgspec

from turtlectl.messages.types import (
    Ack,
    Cancel,
    Clock,
    Kill,
    LaserScan,
    Message,
    Moving,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    ParameterEvent,
    Pose,
    Reset,
    SetLogLevel,
    SetParameter,
    SpawnRequest,
    SpawnResponse,
    TeleportAbsolute,
    Turtles,
    TurtleStatus,
    Twist,
)

#: the turtle the simulator starts with (turtlesim's); others are spawned under their own names
FIRST_TURTLE = "turtle1"


def cmd_vel_key(turtle: str) -> str:
    """Topic on which turtle ``turtle`` takes its velocity commands (Twist)."""
    return f"{turtle}/cmd_vel"


def pose_key(turtle: str) -> str:
    """Topic on which the simulator publishes turtle ``turtle``'s pose (Pose, every step)."""
    return f"{turtle}/pose"


def teleport_key(turtle: str) -> str:
    """Service that puts turtle ``turtle`` somewhere else (TeleportAbsolute -> Ack)."""
    return f"{turtle}/teleport_absolute"


def moving_key(turtle: str) -> str:
    """Service the simulator calls before it moves turtle ``turtle`` (Moving -> Ack): whatever
    drives the turtle stops first (the navigator ends its running goal)."""
    return f"{turtle}/moving"


def resolve(key: str, namespace: str, remaps: Mapping[str, str] | None = None) -> str:
    """The key a node in ``namespace`` uses for ``key`` as its code writes it (ROS's name
    resolution, with turtle1 standing for the namespace's own turtle):

    - a key starting with ``/`` is absolute: the slash dropped, never namespaced (``/chatter``);
    - the runtime's own keys (``turtlectl/...``), liveliness keys (``@...``) and the world's
      (``turtles``, ``spawn``, ``kill``, ``reset``, ``clock``: the simulator's, one for every turtle) never are;
    - with no namespace (``""``), every other key is as written (today's single-turtle system);
    - in namespace ``NS``, the default turtle's keys ``turtle1/X`` are the namespace's turtle's,
      ``NS/X`` (``turtle1/pose`` -> ``turtle2/pose`` in ``turtle2``), and any other key ``K`` is
      ``NS/K`` (``navigate_to`` -> ``turtle2/navigate_to``, ``robot/status`` -> ``turtle2/robot/status``);
    - ``remaps`` (the launch file's ``remap = { FROM = TO }`` of the node, ROS's remappings): a key
      that resolves as ``FROM`` does is ``TO``, resolved the same way.  So ``FROM`` is written as the
      node's code writes the key (``turtle1/cmd_vel``) or absolute (``/turtle2/cmd_vel``); in
      ``turtle2``, ``{ "turtle1/cmd_vel" = "safety/cmd_vel" }`` makes ``turtle2/safety/cmd_vel``.
      A remap names one key: a key expression with wildcards (an interface's ``*/cmd_vel``) is
      never remapped itself (runtime.roles adds the remapped keys it includes).
    """
    resolved = _expand(key, namespace)
    for written, replacement in (remaps or {}).items():
        if _expand(written, namespace) == resolved:
            return _expand(replacement, namespace)
    return resolved


def _expand(key: str, namespace: str) -> str:
    """``resolve`` without remaps: the namespace's part of ROS's name resolution."""
    if key.startswith("/"):
        return key[1:]
    if not namespace or key.startswith(("@", "turtlectl/")) or key.partition("/")[0] in WORLD_KEYS:
        return key
    first, _, rest = key.partition("/")
    if first == FIRST_TURTLE and rest:
        return f"{namespace}/{rest}"
    return f"{namespace}/{key}"


def includes(expression: str, key: str) -> bool:
    """Whether key expression ``expression`` (``*``: one chunk, ``**``: any number of them, as
    Zenoh's) matches every key ``key`` names (itself a key or an expression: it must lie inside).
    Plain string work, for the pure modules (runtime.interface asks Zenoh itself)."""

    def inside(outer: list[str], inner: list[str]) -> bool:
        if not outer:
            return not inner
        if outer[0] == "**":
            return any(inside(outer[1:], inner[i:]) for i in range(len(inner) + 1))
        if not inner or inner[0] == "**":
            return False
        return (outer[0] == inner[0] or (outer[0] == "*" and inner[0] != "")) and inside(outer[1:], inner[1:])

    return inside(expression.split("/"), key.split("/"))


def key_problem(key: str) -> str | None:
    """Why ``key`` cannot be one topic's or service's key as a node writes it (None: it can):
    chunks of letters, digits, ``_``, ``-`` and ``.`` between single ``/`` (one ``/`` first:
    absolute), no wildcard."""
    if not re.fullmatch(r"/?[A-Za-z0-9_.\-]+(/[A-Za-z0-9_.\-]+)*", key):
        return f"{key!r} is not a key: chunks of letters, digits, _, - and . between single /, no wildcard"
    return None


def turtle_namespace(turtle: str, namespaces: Collection[str] = ()) -> str:
    """The namespace of turtle ``turtle``'s nodes, as the tools' ``--turtle`` names it: the
    turtle's name, but turtle1's nodes run outside any namespace ("", the seed's keys
    ``navigate_to``, ``robot/status``) unless nodes run in namespace turtle1 (``namespaces``: the
    namespaces nodes run in, as the live graph shows them); "" for no turtle."""
    if turtle in ("", FIRST_TURTLE) and FIRST_TURTLE not in namespaces:
        return ""
    return turtle


def namespace_of(name: str) -> str:
    """The namespace of a node's full name (``turtle2/navigator`` -> ``turtle2``; ``navigator`` -> "")."""
    return name.rpartition("/")[0]


def turtle_of(namespace: str) -> str:
    """The turtle a namespace's nodes drive (a namespace is a turtle's name; ``turtle_namespace``
    the other way round): the namespace's, or turtle1 outside one."""
    return namespace or FIRST_TURTLE


def name_chunk(name: str) -> str:
    """A node's full name as one key chunk (and file name): ``turtle2/navigator`` ->
    ``turtle2.navigator`` (names have no '.'; ``node_name`` undoes it)."""
    return name.replace("/", ".")


def node_name(chunk: str) -> str:
    """The full name written by ``name_chunk``: ``turtle2.navigator`` -> ``turtle2/navigator``."""
    return chunk.replace(".", "/")


def type_chunk(name: str) -> str:
    """A message type's full name as one key chunk, as a node's: ``capstone_msgs/TurtleStatus``
    -> ``capstone_msgs.TurtleStatus`` (type names have no '.'; ``type_from_chunk`` undoes it)."""
    return name_chunk(name)


def type_from_chunk(chunk: str) -> str:
    """The full name written by ``type_chunk``: ``turtlectl.Pose`` -> ``turtlectl/Pose``."""
    return node_name(chunk)


CMD_VEL = cmd_vel_key(FIRST_TURTLE)
POSE = pose_key(FIRST_TURTLE)
STATUS = "robot/status"
OBSTACLES = "obstacles"
NAVIGATE_TO = "navigate_to"
CANCEL = "navigate_to/cancel"
FEEDBACK = "navigate_to/feedback"
TELEPORT = teleport_key(FIRST_TURTLE)
MOVING = moving_key(FIRST_TURTLE)
RESET = "reset"
SPAWN = "spawn"
KILL = "kill"
TURTLES = "turtles"  # the simulator: every turtle's name and pose
CLOCK = "clock"  # the simulator: its simulated time after every step (ROS's /clock)
#: the ROS 2 bridge: says which ROS 2 domain it bridges (an Ack); serving it is the bridge's claim to
#: be the system's only one, since two bridges of one system on one domain feed each other's topics back
ROS2_BRIDGE = "ros2/bridge"
PARAMETER_EVENTS = "turtlectl/parameter_events"  # every node: a ParameterEvent per change at run time
#: the simulator's keys for the whole world: the same in every namespace (messages.keys.resolve)
WORLD_KEYS = frozenset({TURTLES, SPAWN, KILL, RESET, CLOCK})

TOPICS: dict[str, type[Message]] = {
    CMD_VEL: Twist,
    POSE: Pose,
    STATUS: TurtleStatus,
    OBSTACLES: LaserScan,
    FEEDBACK: NavigateToFeedback,
    PARAMETER_EVENTS: ParameterEvent,
    TURTLES: Turtles,
    CLOCK: Clock,
}

SERVICES: dict[str, tuple[type[Message], type[Message]]] = {
    NAVIGATE_TO: (NavigateToRequest, NavigateToResponse),  # also replies NavigateToFeedback while it runs
    CANCEL: (Cancel, Ack),
    TELEPORT: (TeleportAbsolute, Ack),
    MOVING: (Moving, Ack),
    RESET: (Reset, Ack),  # served by the sim (pose) and the status monitor (battery)
    SPAWN: (SpawnRequest, SpawnResponse),
    KILL: (Kill, Ack),
}

NODE_TOKEN_PREFIX = "@turtlectl/node"
ENTITY_TOKEN_PREFIX = "@turtlectl/entity"
CLIENT_TOKEN_PREFIX = "@turtlectl/client"
#: a client's presence (a tool or a script's Client, while its session is open) and its publishers and
#: subscribers: apart from the nodes', so a client never counts as a node (readiness, claims)
CLIENT_NODE_TOKEN_PREFIX = "@turtlectl/client_node"
CLIENT_ENTITY_TOKEN_PREFIX = "@turtlectl/client_entity"
DOMAIN_TOKEN_PREFIX = "@turtlectl/domain"  # declared, outside any namespace, by a supervisor run with --domain
GRAPH = "@turtlectl/**"  # every node and entity token (and, outside a domain, every domain token)
DOMAIN_GRAPHS = "*/@turtlectl/**"  # outside any domain: the graph of every domain (``*`` matches the domain)


class NodeInfo(msgspec.Struct, frozen=True):
    """A running node as its liveliness token announces it.

    start_ns: wall-clock start time, ns since the epoch.
    """

    name: str
    pid: int
    host: str = ""
    start_ns: int = 0


class NodeDetails(NodeInfo, frozen=True, forbid_unknown_fields=True):
    """What a node answers on ``turtlectl/nodes/<name>`` (JSON): NodeInfo, and its kind (the
    launch file's ``run``) and log level (DEBUG, INFO, WARNING, ERROR); ``errors``: how many
    records at ERROR or worse the process has logged since it started, ``last_error`` the last
    one's message (``verify``'s ``no_errors`` criterion reads them)."""

    kind: str = ""
    log_level: str = "INFO"
    errors: int = 0
    last_error: str = ""
    #: its timers, timeouts and stamps on the simulator's ``clock`` (launch --time-scale, use_sim_time)
    use_sim_time: bool = False


#: an entity token's roles: publisher, subscriber, service, and a goal service's goal, feedback and result types
ENTITY_ROLES = ("pub", "sub", "srv", "goal", "goal_feedback", "goal_result")


class EntityInfo(msgspec.Struct, frozen=True):
    """A publisher ("pub"), subscriber ("sub") or service ("srv") of a node, by its token; a
    goal service ("goal", "goal_feedback", "goal_result": one token for each of its types)."""

    node: str
    pid: int
    role: str
    type_name: str
    key: str


def _chunk(text: str) -> str:
    """``text`` made safe as one key chunk (no '/', '*', '$', '#', '?', '@' at the start)."""
    safe = re.sub(r"[/*$#?\s]", "_", text) or "_"
    return "_" + safe[1:] if safe.startswith("@") else safe


def node_token(info: NodeInfo) -> str:
    """Liveliness key announcing a node: ``@turtlectl/node/<name>/<pid>/<host>/<start_ns>``."""
    return f"{NODE_TOKEN_PREFIX}/{name_chunk(info.name)}/{info.pid}/{_chunk(info.host)}/{info.start_ns}"


def parse_node_token(key: str) -> NodeInfo | None:
    """The NodeInfo in a key made by node_token (host and start may be absent), else None."""
    prefix = NODE_TOKEN_PREFIX + "/"
    if not key.startswith(prefix):
        return None
    parts = key[len(prefix) :].split("/")
    if len(parts) not in (2, 4) or not parts[0] or not parts[1].isdigit():
        return None
    if len(parts) == 4 and not parts[3].isdigit():
        return None
    host, start = (parts[2], int(parts[3])) if len(parts) == 4 else ("", 0)
    return NodeInfo(name=node_name(parts[0]), pid=int(parts[1]), host=host, start_ns=start)


def entity_token(entity: EntityInfo) -> str:
    """Liveliness key announcing an entity: ``@turtlectl/entity/<node>/<pid>/<role>/<package.Type>/<key...>``
    (the type's full name as one chunk, ``turtlectl.Pose``; ``JSON`` for a JSON queryable)."""
    chunk = type_chunk(entity.type_name)
    return f"{ENTITY_TOKEN_PREFIX}/{name_chunk(entity.node)}/{entity.pid}/{entity.role}/{chunk}/{entity.key}"


def parse_entity_token(key: str, kind: str = ENTITY_TOKEN_PREFIX) -> EntityInfo | None:
    """The EntityInfo in a key made by entity_token (``kind``: CLIENT_ENTITY_TOKEN_PREFIX for
    client_entity_token's), else None."""
    prefix = kind + "/"
    if not key.startswith(prefix):
        return None
    parts = key[len(prefix) :].split("/", 4)
    if len(parts) != 5 or not parts[1].isdigit() or parts[2] not in ENTITY_ROLES:
        return None
    return EntityInfo(
        node=node_name(parts[0]), pid=int(parts[1]), role=parts[2], type_name=type_from_chunk(parts[3]), key=parts[4]
    )


class ClientInfo(NodeInfo, frozen=True):
    """A client (a command-line tool or a script's ``turtlectl.Client``) as its presence token
    announces it while its session is open: its name (``teleop-4242``: the tool and its pid),
    pid, host, start and ``tool`` (teleop, goto, echo, record, plot, ...; python for a script's
    Client)."""

    tool: str = ""


def client_node_token(info: ClientInfo) -> str:
    """Liveliness key announcing a client: ``@turtlectl/client_node/<name>/<pid>/<host>/<start_ns>/<tool>``."""
    host = _chunk(info.host)
    return f"{CLIENT_NODE_TOKEN_PREFIX}/{name_chunk(info.name)}/{info.pid}/{host}/{info.start_ns}/{_chunk(info.tool)}"


def parse_client_node_token(key: str) -> ClientInfo | None:
    """The ClientInfo in a key made by client_node_token, else None."""
    prefix = CLIENT_NODE_TOKEN_PREFIX + "/"
    parts = key[len(prefix) :].split("/") if key.startswith(prefix) else []
    if len(parts) != 5 or not parts[0] or not parts[1].isdigit() or not parts[3].isdigit():
        return None
    return ClientInfo(name=node_name(parts[0]), pid=int(parts[1]), host=parts[2], start_ns=int(parts[3]), tool=parts[4])


def client_entity_token(entity: EntityInfo) -> str:
    """Liveliness key announcing a client's publisher or subscriber, as entity_token's for a
    node: ``@turtlectl/client_entity/<client>/<pid>/<role>/<package.Type>/<key...>``."""
    return CLIENT_ENTITY_TOKEN_PREFIX + entity_token(entity)[len(ENTITY_TOKEN_PREFIX) :]


def client_token(client_id: str) -> str:
    """Liveliness key a caller of ``navigate_to`` holds while it waits: ``@turtlectl/client/<id>``,
    where ``<id>`` is what it puts in ``NavigateToRequest.client``."""
    return f"{CLIENT_TOKEN_PREFIX}/{client_id}"


def domain_token(domain: str) -> str:
    """Liveliness key, outside any namespace, announcing that a system runs in ``domain``."""
    return f"{DOMAIN_TOKEN_PREFIX}/{domain}"


def parse_domain_token(key: str) -> str | None:
    """The domain named by a key made by domain_token, else None."""
    prefix = DOMAIN_TOKEN_PREFIX + "/"
    rest = key[len(prefix) :] if key.startswith(prefix) else ""
    return rest if rest and "/" not in rest else None


WORLD_KEY = "turtlectl/world"  # the sim answers with the world (size, obstacles) as JSON


def params_key(name: str) -> str:
    """Queryable on which node ``name`` answers with its parameters (JSON)."""
    return f"turtlectl/params/{name_chunk(name)}"


def param_set_key(name: str) -> str:
    """Service on which node ``name`` changes one of its parameters (SetParameter -> Ack)."""
    return f"{params_key(name)}/set"


def param_describe_key(name: str) -> str:
    """Queryable on which node ``name`` describes its parameters (JSON ParamDescription:
    types, units, ranges, defaults, values now, whether each can change at run time)."""
    return f"{params_key(name)}/describe"


def node_key(name: str) -> str:
    """Queryable on which node ``name`` answers what it is (JSON): its kind, pid, host, start,
    log level."""
    return f"turtlectl/nodes/{name_chunk(name)}"


TYPES = "turtlectl/types"  # every node: the description of each message type it uses (JSON)


def type_key(type_name: str, node: str) -> str:
    """Queryable on which ``node`` describes the message type ``type_name`` it uses (JSON
    TypeDescription, messages.described), its full name as one chunk:
    ``turtlectl/types/capstone_msgs.TurtleStatus/<node>``; ``turtlectl/types/<chunk>/*`` asks every
    node that uses it, ``turtlectl/types/*/*`` every type in use."""
    return f"{TYPES}/{type_chunk(type_name)}/{name_chunk(node)}"


def log_level_key(name: str) -> str:
    """Service on which node ``name`` changes its log level (SetLogLevel -> Ack)."""
    return f"{node_key(name)}/log_level"


LOG = "turtlectl/log"  # every node: each record of its log (Log), on a key of its own below
#: every node's log key: subscribe to it for the records as they come, get it for each node's recent ones
LOG_KEYS = f"{LOG}/*"


def log_key(name: str) -> str:
    """Topic on which node ``name`` publishes each record of its log (Log), and queryable on
    which it answers with its recent records (one Log reply each, oldest first):
    ``turtlectl/log/turtle2.navigator`` for ``turtle2/navigator``."""
    return f"{LOG}/{name_chunk(name)}"


def service_types(key: str) -> tuple[type[Message], type[Message]] | None:
    """(request, response) types of the service at ``key``: a fixed key of SERVICES, or one
    every node serves (``turtlectl/params/<node>/set``, ``turtlectl/nodes/<node>/log_level``)."""
    if key in SERVICES:
        return SERVICES[key]
    parts = key.split("/")
    if len(parts) == 2 and parts[1] == "teleport_absolute" and parts[0] not in ("", "*", "**"):
        return TeleportAbsolute, Ack  # any turtle's

    if len(parts) == 4 and parts[0] == "turtlectl" and parts[2]:
        if (parts[1], parts[3]) == ("params", "set"):
            return SetParameter, Ack
        if (parts[1], parts[3]) == ("nodes", "log_level"):
            return SetLogLevel, Ack
    return None
