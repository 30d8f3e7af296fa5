"""The kinds of node a launch file can run: the module to start and its parameters."""

from __future__ import annotations

import msgspec

from nodes.params import NavigatorParams, ObstacleDetectorParams, StatusMonitorParams
from sim.params import SimParams


class NodeKind(msgspec.Struct, frozen=True):
    module: str  # run as ``python -m <module>``
    params: type[msgspec.Struct]


KINDS: dict[str, NodeKind] = {
    "sim": NodeKind("sim.node", SimParams),
    "navigator": NodeKind("nodes.navigator", NavigatorParams),
    "status_monitor": NodeKind("nodes.status_monitor", StatusMonitorParams),
    "obstacle_detector": NodeKind("nodes.obstacle_detector", ObstacleDetectorParams),
}
