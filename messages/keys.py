"""Key expressions: which message type travels on which key.

Topics are plain keys (no leading slash, as Zenoh wants).  Liveliness tokens
live under ``@turtlectl/node/<name>/<pid>`` so that ``**`` on the data space
never matches them.
"""

from __future__ import annotations

from messages.types import (
    Ack,
    Cancel,
    LaserScan,
    Message,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    Reset,
    TeleportAbsolute,
    TurtleStatus,
    Twist,
)

CMD_VEL = "turtle1/cmd_vel"
POSE = "turtle1/pose"
STATUS = "robot/status"
OBSTACLES = "obstacles"
NAVIGATE_TO = "navigate_to"
CANCEL = "navigate_to/cancel"
TELEPORT = "turtle1/teleport_absolute"
RESET = "reset"

TOPICS: dict[str, type[Message]] = {
    CMD_VEL: Twist,
    POSE: Pose,
    STATUS: TurtleStatus,
    OBSTACLES: LaserScan,
}

SERVICES: dict[str, tuple[type[Message], type[Message]]] = {
    NAVIGATE_TO: (NavigateToRequest, NavigateToResponse),  # also replies NavigateToFeedback while it runs
    CANCEL: (Cancel, Ack),
    TELEPORT: (TeleportAbsolute, Ack),
    RESET: (Reset, Ack),  # served by the sim (pose) and the status monitor (battery)
}

NODE_TOKEN_PREFIX = "@turtlectl/node"
CLIENT_TOKEN_PREFIX = "@turtlectl/client"


def node_token(name: str, pid: int) -> str:
    """Liveliness key announcing node ``name`` running as process ``pid``."""
    return f"{NODE_TOKEN_PREFIX}/{name}/{pid}"


def parse_node_token(key: str) -> tuple[str, int] | None:
    """(name, pid) from a liveliness key made by node_token, else None."""
    prefix = NODE_TOKEN_PREFIX + "/"
    if not key.startswith(prefix):
        return None
    name, _, pid = key[len(prefix):].partition("/")
    if not name or not pid.isdigit():
        return None
    return name, int(pid)


def params_key(name: str) -> str:
    """Queryable on which node ``name`` answers with its parameters (JSON)."""
    return f"turtlectl/params/{name}"
