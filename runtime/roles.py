"""The roles of a ``launch --secure`` system's clients, and what a user's node class that declares
no ``Interface`` may do (pure data: cli.system.access turns them into the router's rules, the
supervisor hands a node its interface, the node's runtime (and runtime.fake) refuses anything else).

* ``viewer``: echo, hz, list, view, record, node/topic info, param get (subscribe to
  everything, read the JSON answers, follow the graph);
* ``operator``: also goto, cancel, teleport (any turtle), reset, spawn, kill, call, param set, log-level;
* ``teleop``: also publishes every turtle's ``<turtle>/cmd_vel`` (teleop, pub).
"""

from __future__ import annotations

from turtlectl.messages.keys import (
    CANCEL,
    CLIENT_TOKEN_PREFIX,
    KILL,
    NAVIGATE_TO,
    RESET,
    SPAWN,
    TYPES,
    WORLD_KEY,
    cmd_vel_key,
    log_level_key,
    namespace_of,
    node_key,
    param_describe_key,
    param_set_key,
    params_key,
    resolve,
    teleport_key,
)
from turtlectl.runtime.config import Claim, Interface

GRAPH_KEYS = ("@turtlectl/**", "*/@turtlectl/**")  # the graph, and (outside a domain) every domain's
VIEWER: dict[str, tuple[str, ...]] = {
    "subscribe": ("**",),
    "call": (params_key("*"), param_describe_key("*"), node_key("*"), WORLD_KEY, f"{TYPES}/**"),
    "watch": GRAPH_KEYS,
}
OPERATOR: dict[str, tuple[str, ...]] = {
    **VIEWER,
    "call": (
        *VIEWER["call"],
        NAVIGATE_TO,  # the turtle outside any namespace, and every namespace's (goto --turtle)
        f"**/{NAVIGATE_TO}",
        CANCEL,
        f"**/{CANCEL}",
        teleport_key("*"),
        RESET,
        SPAWN,
        KILL,
        param_set_key("*"),
        log_level_key("*"),
    ),
    "token": (f"{CLIENT_TOKEN_PREFIX}/**",),  # a goal's caller holds one while it waits
}
ROLES: dict[str, dict[str, tuple[str, ...]]] = {
    "viewer": VIEWER,
    "operator": OPERATOR,
    "teleop": {**OPERATOR, "publish": (cmd_vel_key("*"),)},  # every turtle's (turtle1's among them)
}


def undeclared(name: str) -> Interface:
    """What a user's node class that declares no Interface may do: what a ``teleop`` client
    may (subscribe to everything, the operator's calls, cmd_vel, a caller's token), and
    publish and serve under its own name."""
    teleop = ROLES["teleop"]
    return Interface(
        publishes=(*teleop["publish"], f"{name}/**"),
        subscribes=teleop["subscribe"],
        serves=(f"{name}/**",),
        calls=teleop["call"],
        watches=teleop["watch"],
    )


def interface_of(name: str, declared: Interface | None) -> Interface:
    """What node ``name`` (its full name: ``turtle2/navigator`` is in namespace ``turtle2``) may
    do beyond every node's share: the interface its kind declares, its keys resolved in the
    node's namespace (messages.keys.resolve), or ``undeclared(name)``'s.  The one source for
    the router's rules and the node's runtime."""
    if declared is None:
        return undeclared(name)
    namespace = namespace_of(name)

    def keys(written: tuple[str, ...]) -> tuple[str, ...]:
        return tuple(resolve(key, namespace) for key in written)

    return Interface(
        publishes=keys(declared.publishes),
        subscribes=keys(declared.subscribes),
        serves=keys(declared.serves),
        calls=keys(declared.calls),
        watches=keys(declared.watches),
    )


def claims_of(name: str, claims: tuple[Claim, ...] | list[Claim]) -> list[Claim]:
    """What node ``name`` claims alone, its keys resolved in its namespace: one navigator per
    namespace serves its ``navigate_to`` (``turtle2/navigate_to``)."""
    namespace = namespace_of(name)
    return [Claim(claim.role, resolve(claim.key, namespace)) for claim in claims]
