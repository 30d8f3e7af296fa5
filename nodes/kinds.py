"""The node kinds a launch file can run, in one registry that built-in kinds and a user's node
classes both go through (``kind_of``): the class to run and how to start it, its parameters,
what only one node of a system may do (checked by the runtime before the node starts, and by
the launch file's validation), and what it publishes, subscribes to, serves and calls (what a
``launch --secure`` router lets each node do, and nothing else).

A ``run`` is a built-in kind's name (``KINDS``) or a user's node class, ``module:Class`` or
``./file.py:Class`` (runtime.loader: the class's ``Params`` is its parameter Struct; it may
also declare ``Claims``, a tuple of runtime.config.Claim, and ``Interface``, an Interface).
A kind's ``Params`` may narrow its ``Interface`` by what a node's parameters say it will do,
with a method ``narrow_interface(interface) -> Interface`` (the ROS 2 bridge: the keys of its
table); the launch file's validation applies it, so the node and a ``--secure`` router both get
the narrowed one.  A built-in kind is forked by the zygote from its module's ``main``; a user's class is started
by exec, ``python -m turtlectl.runtime TARGET`` (why: runtime/__main__.py).
"""

from __future__ import annotations

from pathlib import Path

import msgspec

from turtlectl.nodes.params import (
    NAVIGATOR_CLAIMS,
    NAVIGATOR_INTERFACE,
    OBSTACLE_DETECTOR_CLAIMS,
    OBSTACLE_DETECTOR_INTERFACE,
    ROS2_BRIDGE_CLAIMS,
    ROS2_BRIDGE_INTERFACE,
    STATUS_MONITOR_CLAIMS,
    STATUS_MONITOR_INTERFACE,
    WEB_INTERFACE,
    NavigatorParams,
    ObstacleDetectorParams,
    Ros2BridgeParams,
    StatusMonitorParams,
    WebParams,
)
from turtlectl.runtime.client.errors import BadInput
from turtlectl.runtime.config import Claim, Interface
from turtlectl.runtime.loader import LoadError, absolute, is_target, load, suggestion
from turtlectl.sim.params import SIM_CLAIMS, SIM_INTERFACE, SimParams


class NodeKind(msgspec.Struct, frozen=True):
    target: str  # the class: ``module:Class``, or ``/absolute/file.py:Class`` for a user's file
    params: type[msgspec.Struct]
    claims: tuple[Claim, ...] = ()  # so two nodes claiming the same in one system clash
    interface: Interface | None = None  # None: not declared (a user's kind; see cli.system.access)
    builtin: bool = False  # forked by the zygote from its module's main(), else exec'd by runtime.__main__

    @property
    def module(self) -> str:
        """The module that defines the class (a built-in's runs as ``python -m <module>``)."""
        return self.target.rpartition(":")[0]

    def owns(self) -> str:
        """What two nodes of this kind would both do, e.g. 'publish turtle1/pose'."""
        return " and ".join(claim.phrase() for claim in self.claims)


def _builtin(target: str, params: type[msgspec.Struct], claims: tuple[Claim, ...], interface: Interface) -> NodeKind:
    """A built-in kind: its class's ``Params``, ``Claims`` and ``Interface``, declared once beside
    its parameters (nodes.params, sim.params) so that this registry stays pure."""
    return NodeKind(target, params, claims, interface, builtin=True)


class KindError(BadInput, ValueError):
    """A ``run`` that names no kind: str() is the one line saying why (exit code 2)."""


def kind_of(run: str, base: Path) -> NodeKind:
    """The kind a launch file's ``run`` names: a built-in kind, or a user's node class (imported
    now, here: ``module:Class`` from sys.path, ``file.py:Class`` relative to ``base``).  Raises
    KindError naming what is wrong (unknown, does not import and why, not a node class)."""
    if not is_target(run):
        kind = KINDS.get(run)
        if kind is None:
            known = ", ".join(sorted(KINDS))
            raise KindError(
                f"unknown node kind {run!r}{suggestion(run, tuple(KINDS))} (known: {known}; or a node class: module:Class, ./file.py:Class)"
            )
        return kind
    try:
        cls, params = load(run, base)
    except LoadError as exc:
        raise KindError(str(exc)) from None
    claims = getattr(cls, "Claims", ())
    if not (isinstance(claims, tuple) and all(isinstance(c, Claim) for c in claims)):
        raise KindError(f"{run}: Claims must be a tuple of turtlectl.Claim")
    interface = getattr(cls, "Interface", None)
    if interface is not None and not isinstance(interface, Interface):
        raise KindError(f"{run}: Interface must be a turtlectl.Interface")
    return NodeKind(absolute(run, base), params, claims, interface)


KINDS: dict[str, NodeKind] = {
    "sim": _builtin("turtlectl.sim.node:Simulator", SimParams, SIM_CLAIMS, SIM_INTERFACE),
    "navigator": _builtin(
        "turtlectl.nodes.navigator:Navigator", NavigatorParams, NAVIGATOR_CLAIMS, NAVIGATOR_INTERFACE
    ),
    "status_monitor": _builtin(
        "turtlectl.nodes.status_monitor:StatusMonitor",
        StatusMonitorParams,
        STATUS_MONITOR_CLAIMS,
        STATUS_MONITOR_INTERFACE,
    ),
    "obstacle_detector": _builtin(
        "turtlectl.nodes.obstacle_detector:ObstacleDetector",
        ObstacleDetectorParams,
        OBSTACLE_DETECTOR_CLAIMS,
        OBSTACLE_DETECTOR_INTERFACE,
    ),
    "ros2_bridge": _builtin(
        "turtlectl.nodes.ros2_bridge:Ros2Bridge", Ros2BridgeParams, ROS2_BRIDGE_CLAIMS, ROS2_BRIDGE_INTERFACE
    ),
    # the web page is a tool of the command line's layer (it does what the commands do), so it is named,
    # not imported, here, and started as a user's node class is: by exec (runtime/__main__.py)
    "web": NodeKind("turtlectl.cli.web.node:Web", WebParams, (), WEB_INTERFACE),
}
