"""The kinds of node a launch file can run: the module to start, its parameters, and what
only one node of a system may do (checked by the runtime before the node starts, and by
the launch file's validation)."""

from __future__ import annotations

import msgspec

from messages.keys import NAVIGATE_TO, OBSTACLES, POSE, STATUS
from nodes.params import NavigatorParams, ObstacleDetectorParams, StatusMonitorParams
from runtime.config import Claim
from sim.params import SimParams


class NodeKind(msgspec.Struct, frozen=True):
    module: str  # run as ``python -m <module>``
    params: type[msgspec.Struct]
    claims: tuple[Claim, ...] = ()  # so two nodes of this kind in one system clash

    def owns(self) -> str:
        """What two nodes of this kind would both do, e.g. 'publish turtle1/pose'."""
        return " and ".join(claim.phrase() for claim in self.claims)


KINDS: dict[str, NodeKind] = {
    "sim": NodeKind("sim.node", SimParams, (Claim("pub", POSE),)),
    "navigator": NodeKind("nodes.navigator", NavigatorParams, (Claim("srv", NAVIGATE_TO),)),
    "status_monitor": NodeKind("nodes.status_monitor", StatusMonitorParams, (Claim("pub", STATUS),)),
    "obstacle_detector": NodeKind("nodes.obstacle_detector", ObstacleDetectorParams, (Claim("pub", OBSTACLES),)),
}
