"""The kinds of node a launch file can run: the module to start, its parameters, what only
one node of a system may do (checked by the runtime before the node starts, and by the
launch file's validation), and what it publishes, subscribes to, serves and calls (what a
``launch --secure`` router lets each node do, and nothing else)."""

from __future__ import annotations

import msgspec

from messages.keys import (
    CANCEL,
    CLIENT_TOKEN_PREFIX,
    CMD_VEL,
    FEEDBACK,
    NAVIGATE_TO,
    OBSTACLES,
    POSE,
    RESET,
    STATUS,
    TELEPORT,
    WORLD_KEY,
)
from nodes.params import NavigatorParams, ObstacleDetectorParams, StatusMonitorParams
from runtime.config import Claim
from sim.params import SimParams


class Interface(msgspec.Struct, frozen=True):
    """The keys a node kind uses, beyond what every node does (its parameters, node info, log
    level, parameter events and liveliness tokens: the runtime's)."""

    publishes: tuple[str, ...] = ()
    subscribes: tuple[str, ...] = ()
    serves: tuple[str, ...] = ()
    calls: tuple[str, ...] = ()
    watches: tuple[str, ...] = ()  # liveliness tokens it follows


class NodeKind(msgspec.Struct, frozen=True):
    module: str  # run as ``python -m <module>``
    params: type[msgspec.Struct]
    claims: tuple[Claim, ...] = ()  # so two nodes of this kind in one system clash
    interface: Interface = Interface()

    def owns(self) -> str:
        """What two nodes of this kind would both do, e.g. 'publish turtle1/pose'."""
        return " and ".join(claim.phrase() for claim in self.claims)


KINDS: dict[str, NodeKind] = {
    "sim": NodeKind(
        "sim.node",
        SimParams,
        (Claim("pub", POSE),),
        Interface(publishes=(POSE,), subscribes=(CMD_VEL,), serves=(TELEPORT, RESET, WORLD_KEY), calls=(CANCEL,)),
    ),
    "navigator": NodeKind(
        "nodes.navigator",
        NavigatorParams,
        (Claim("srv", NAVIGATE_TO),),
        Interface(
            publishes=(CMD_VEL, FEEDBACK),
            subscribes=(POSE, STATUS, OBSTACLES),
            serves=(NAVIGATE_TO, CANCEL),
            watches=(f"{CLIENT_TOKEN_PREFIX}/**",),
        ),
    ),
    "status_monitor": NodeKind(
        "nodes.status_monitor",
        StatusMonitorParams,
        (Claim("pub", STATUS),),
        Interface(publishes=(STATUS,), subscribes=(POSE,), serves=(RESET,)),
    ),
    "obstacle_detector": NodeKind(
        "nodes.obstacle_detector",
        ObstacleDetectorParams,
        (Claim("pub", OBSTACLES),),
        Interface(publishes=(OBSTACLES,), subscribes=(POSE,)),
    ),
}
