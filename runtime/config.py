"""What the supervisor hands to each node process (pure: no zenoh).

The supervisor serialises a NodeConfig to JSON in the environment variable
``TURTLECTL_NODE_CONFIG``; the node runtime reads it back and decodes the
``params`` table into the node kind's parameter Struct.
"""

from __future__ import annotations

from typing import Any, Literal

import msgspec

from turtlectl.messages.world import Limits, World

ENV_VAR = "TURTLECTL_NODE_CONFIG"
SUPERVISOR_PID_VAR = "TURTLECTL_SUPERVISOR_PID"
#: the launch file's folder, given to every node it starts: where a built-in node imports a user's module
#: from (a message type of the user's that the ROS 2 bridge's rows name)
PROJECT_VAR = "TURTLECTL_PROJECT"
#: the levels a node's log can be set to (``launch --log-level``, ``turtlectl log-level``)
LOG_LEVELS = ("DEBUG", "INFO", "WARNING", "ERROR")


class Claim(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """What only one node of a system may do: publish ("pub") or serve ("srv") ``key``.

    A node class declares its claims once, ``Claims = (Claim("pub", "patrol/state"),)``;
    ``launch --check`` and the runtime (before the node starts) refuse a second node claiming the same."""

    role: Literal["pub", "srv"]
    key: str

    def phrase(self, third_person: bool = False) -> str:
        """'publish turtle1/pose', or with ``third_person`` 'publishes turtle1/pose'."""
        verb = {"pub": "publish", "srv": "serve"}[self.role]
        return f"{verb}{'es' if third_person and verb.endswith('sh') else 's' if third_person else ''} {self.key}"


class Interface(msgspec.Struct, frozen=True):
    """What a node publishes, subscribes to, serves, calls and watches (liveliness), as key
    expressions, beyond what every node does (its parameters, node info, log level, parameter
    events and liveliness tokens: the runtime's).  A node class declares it once,
    ``Interface = Interface(publishes=("patrol/state",), calls=("navigate_to",))``: the runtime
    refuses any other declaration, and a ``launch --secure`` router allows exactly this.
    ``goals=("navigate_to",)`` declares a goal service whole (runtime.roles.interface_of expands it)."""

    publishes: tuple[str, ...] = ()
    subscribes: tuple[str, ...] = ()
    serves: tuple[str, ...] = ()
    calls: tuple[str, ...] = ()
    watches: tuple[str, ...] = ()  # liveliness tokens it follows
    #: goal services it serves (``Node.goal_server``): each ``KEY`` stands for what its server
    #: declares, ``KEY`` and ``KEY/cancel`` served, ``KEY/feedback`` published, callers' tokens watched
    goals: tuple[str, ...] = ()


class Credentials(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """A user name and password a router of a ``launch --secure`` system accepts (Zenoh's
    user/password authentication)."""

    user: str
    password: str


class NodeConfig(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    name: str
    kind: str
    connect: str
    domain: str = ""  # a Zenoh namespace that prefixes every key of the system (isolation)
    params: dict[str, Any] = msgspec.field(default_factory=dict)
    #: what the node may declare beyond every node's share (its kind's Interface, or what an
    #: undeclared user kind may do); the runtime refuses anything else.  None: no check
    interface: Interface | None = None
    claims: list[Claim] = msgspec.field(default_factory=list)  # checked before the node starts
    #: the launch file's ``remap`` of the node (ROS's remappings): a key its code writes as FROM is
    #: TO, both resolved in its namespace (messages.keys.resolve); interface and claims already say so
    remaps: dict[str, str] = msgspec.field(default_factory=dict)
    world: World = msgspec.field(default_factory=World)
    limits: Limits = msgspec.field(default_factory=Limits)
    log_level: Literal["DEBUG", "INFO", "WARNING", "ERROR"] = "INFO"
    #: timers, clock() and stamps on the simulator's ``clock`` key (runtime.simtime), not the machine's
    use_sim_time: bool = False
    # a --secure system: the node's own credentials; it is then a client of the router, never a
    # peer others could reach directly (the router authenticates every session)
    credentials: Credentials | None = None


def encode_config(config: NodeConfig) -> str:
    return msgspec.json.encode(config).decode()


def decode_config(text: str) -> NodeConfig:
    """Raises msgspec.ValidationError / DecodeError with the offending path."""
    return msgspec.json.decode(text, type=NodeConfig)
