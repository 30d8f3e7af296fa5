"""The roles of a ``launch --secure`` system's clients, and what a user's node class that declares
no ``Interface`` may do (pure data: cli.system.access turns them into the router's rules, the
supervisor hands a node its interface, the node's runtime (and runtime.fake) refuses anything else).

* ``viewer``: echo, hz, list, view, record, log, node/topic info, param get (subscribe to
  everything, read the JSON answers and the nodes' recent log records, follow the graph, and
  be listed in it: every client declares its presence, ``PRESENCE_KEYS``);
* ``operator``: also goto, cancel, teleport (any turtle), reset, spawn, kill, call, param set, log-level,
  and send goals to and cancel the goals of every goal service the system's nodes serve
  (``GOAL_SENDERS``, ``client_rights``);
* ``teleop``: also publishes every turtle's ``<turtle>/cmd_vel`` (teleop, pub).
"""

from __future__ import annotations

from collections.abc import Mapping

import msgspec

from turtlectl.messages.keys import (
    CANCEL,
    CLIENT_ENTITY_TOKEN_PREFIX,
    CLIENT_NODE_TOKEN_PREFIX,
    CLIENT_TOKEN_PREFIX,
    KILL,
    LOG_KEYS,
    NAVIGATE_TO,
    RESET,
    SPAWN,
    TYPES,
    WORLD_KEY,
    cmd_vel_key,
    includes,
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
#: every client's presence in the graph, and its publishers and subscribers (runtime.client.presence)
PRESENCE_KEYS = (f"{CLIENT_NODE_TOKEN_PREFIX}/**", f"{CLIENT_ENTITY_TOKEN_PREFIX}/**")
VIEWER: dict[str, tuple[str, ...]] = {
    "subscribe": ("**",),
    "call": (params_key("*"), param_describe_key("*"), node_key("*"), WORLD_KEY, f"{TYPES}/**", LOG_KEYS),
    "watch": GRAPH_KEYS,
    "token": PRESENCE_KEYS,
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
    "token": (*PRESENCE_KEYS, f"{CLIENT_TOKEN_PREFIX}/**"),  # a goal's caller holds one while it waits
}
ROLES: dict[str, dict[str, tuple[str, ...]]] = {
    "viewer": VIEWER,
    "operator": OPERATOR,
    "teleop": {**OPERATOR, "publish": (cmd_vel_key("*"),)},  # every turtle's (turtle1's among them)
}

#: the roles that may send a goal to every goal service the system's nodes serve, and cancel it
GOAL_SENDERS = ("operator", "teleop")


def goal_services(interface: Interface) -> tuple[str, ...]:
    """The goal services ``interface`` serves: those its ``goals`` names, and each key expression
    ``KEY`` it serves together with ``KEY/cancel`` (a goal server serves both: runtime.goals).  A
    node class that declares no Interface serves ``<name>/**``: every service under its name may be one."""
    served = (key for key in interface.serves if any(includes(other, f"{key}/cancel") for other in interface.serves))
    return tuple(dict.fromkeys([*interface.goals, *served]))


def with_goal_services(interface: Interface) -> Interface:
    """``interface`` with each goal service of its ``goals`` spelled out as its server declares
    it (runtime.goals): ``KEY`` and ``KEY/cancel`` served, ``KEY/feedback`` published, the callers'
    liveliness tokens watched."""
    goals = interface.goals
    if not goals:
        return interface
    return msgspec.structs.replace(
        interface,
        publishes=(*interface.publishes, *(f"{key}/feedback" for key in goals)),
        serves=(*interface.serves, *(k for key in goals for k in (key, f"{key}/cancel"))),
        watches=(*interface.watches, f"{CLIENT_TOKEN_PREFIX}/**"),
    )


def client_rights(role: str, goals: tuple[str, ...] | list[str] = ()) -> dict[str, tuple[str, ...]]:
    """What a client of ``role`` may do on a system whose nodes serve the goal services
    ``goals`` (``goal_services`` of each node's interface): its role's table, and for the
    ``GOAL_SENDERS`` a call on each ``KEY`` and ``KEY/cancel``."""
    rights = ROLES[role]
    if role not in GOAL_SENDERS or not goals:
        return rights
    calls = (*rights["call"], *(k for key in goals for k in (key, f"{key}/cancel")))
    return {**rights, "call": tuple(dict.fromkeys(calls))}


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


def interface_of(name: str, declared: Interface | None, remaps: Mapping[str, str] | None = None) -> Interface:
    """What node ``name`` (its full name: ``turtle2/navigator`` is in namespace ``turtle2``) may
    do beyond every node's share: the interface its kind declares, its keys resolved in the
    node's namespace with its ``remaps`` (messages.keys.resolve), or ``undeclared(name)``'s.  The
    one source for the router's rules and the node's runtime.  A remapped key takes the place of
    the key the interface names; one that a wider expression names (the simulator's
    ``*/cmd_vel``) is added beside it, which still names the node's other keys."""
    namespace = namespace_of(name)
    # each remapped key as the node would use it -> the key it uses instead
    remapped = {resolve(source, namespace): resolve(source, namespace, remaps) for source in remaps or {}}
    interface = undeclared(name) if declared is None else with_goal_services(declared)

    def keys(written: tuple[str, ...]) -> tuple[str, ...]:
        # undeclared's keys are as they are; a declared interface's are written as the node's code writes them
        used = list(written) if declared is None else [resolve(key, namespace) for key in written]
        wider = [to for key, to in remapped.items() if any(u != key and includes(u, key) for u in used)]
        return tuple(dict.fromkeys([remapped.get(u, u) for u in used] + wider))

    return Interface(
        publishes=keys(interface.publishes),
        subscribes=keys(interface.subscribes),
        serves=keys(interface.serves),
        calls=keys(interface.calls),
        watches=keys(interface.watches),
        goals=keys(interface.goals),
    )


def claims_of(
    name: str, claims: tuple[Claim, ...] | list[Claim], remaps: Mapping[str, str] | None = None
) -> list[Claim]:
    """What node ``name`` claims alone, its keys resolved in its namespace with its ``remaps``:
    one navigator per namespace serves its ``navigate_to`` (``turtle2/navigate_to``)."""
    namespace = namespace_of(name)
    return [Claim(claim.role, resolve(claim.key, namespace, remaps)) for claim in claims]
