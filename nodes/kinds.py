"""The kinds of node a launch file can run: the module to start and its parameters."""

from __future__ import annotations

import msgspec

from messages.keys import NAVIGATE_TO, OBSTACLES, POSE, STATUS
from nodes.params import NavigatorParams, ObstacleDetectorParams, StatusMonitorParams
from sim.params import SimParams


class NodeKind(msgspec.Struct, frozen=True):
    module: str  # run as ``python -m <module>``
    params: type[msgspec.Struct]
    # what every node of this kind does on a fixed key, so two of them in one system clash
    owns: str = ""


KINDS: dict[str, NodeKind] = {
    "sim": NodeKind("sim.node", SimParams, f"publish {POSE}"),
    "navigator": NodeKind("nodes.navigator", NavigatorParams, f"serve {NAVIGATE_TO}"),
    "status_monitor": NodeKind("nodes.status_monitor", StatusMonitorParams, f"publish {STATUS}"),
    "obstacle_detector": NodeKind("nodes.obstacle_detector", ObstacleDetectorParams, f"publish {OBSTACLES}"),
}
