"""What each session of a ``launch --secure`` system may do (pure data: the router's
``access_control`` section, deny by default, and the same table for the clients' own check).

Each node logs in as ``node-<name>`` and may do what its kind declares (nodes.kinds.Interface)
and what the runtime does for every node (its parameters, node info, log level, parameter
events, log records, liveliness tokens).  A user's node class that declares no ``Interface`` may do what
the ``teleop`` role may (a local client of the system may do as much) and publish and serve
under its own name (``<name>/**``); nothing else (``UNDECLARED``).  Clients log in with a role:

* ``viewer``: echo, hz, list, view, record, log, node/topic info, param get (subscribe to
  everything, read the JSON answers and the nodes' recent log records, follow the graph, and
  declare its presence in it, as every client does: ``roles.PRESENCE_KEYS``);
* ``operator``: also goto, cancel, teleport, reset, call, param set, log-level, and send goals
  to and cancel the goals of every goal service the launch's nodes serve (``client_rights``);
* ``teleop``: also publishes ``turtle1/cmd_vel`` (teleop, pub).

Zenoh drops a denied message silently, so the command line checks its role first and says
"not permitted" (runtime.client.session.permitted); the router's rules are what holds against anyone else.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from turtlectl.messages.keys import (
    CLOCK,
    ENTITY_TOKEN_PREFIX,
    LOG_KEYS,
    NODE_TOKEN_PREFIX,
    PARAMETER_EVENTS,
    log_key,
    log_level_key,
    name_chunk,
    node_key,
    param_describe_key,
    param_set_key,
    params_key,
    type_key,
)
from turtlectl.runtime.roles import (
    GRAPH_KEYS,
    OPERATOR,
    ROLES,
    VIEWER,
    client_rights,
    goal_services,
    interface_of,
    undeclared,
)

if TYPE_CHECKING:  # the clients' check (runtime.client.session.permitted) needs no node kind
    from turtlectl.nodes.kinds import NodeKind

__all__ = [
    "GRAPH_KEYS",
    "OPERATOR",
    "ROLES",
    "VIEWER",
    "access_control",
    "client_rights",
    "launch_goal_services",
    "node_rights",
    "undeclared",
]

#: a verb -> the Zenoh messages it takes, each with its direction at the router
#: (ingress: from the session; egress: to it)
VERBS: dict[str, tuple[tuple[str, str], ...]] = {
    # a publisher hears of the subscribers (and sends only where one listens)
    "publish": (("put", "ingress"), ("delete", "ingress"), ("declare_subscriber", "egress")),
    "subscribe": (("declare_subscriber", "ingress"), ("put", "egress"), ("delete", "egress")),
    "serve": (("declare_queryable", "ingress"), ("query", "egress"), ("reply", "ingress")),
    "call": (("query", "ingress"), ("reply", "egress"), ("declare_queryable", "egress")),
    # a query for every node at once (turtlectl/nodes/*) reaches a node only through a rule as wide
    "asked": (("query", "egress"),),
    # likewise a subscriber on a wildcard (turtlectl/log/*, record's **): a publisher hears of it,
    # and sends to it, only through a rule that includes the wildcard (what it may put is "publish")
    "heard": (("declare_subscriber", "egress"),),
    "token": (("liveliness_token", "ingress"),),
    "watch": (
        ("declare_liveliness_subscriber", "ingress"),
        ("liveliness_query", "ingress"),
        ("liveliness_token", "egress"),
        ("reply", "egress"),
    ),
}


def node_rights(name: str, kind: NodeKind, remaps: dict[str, str] | None = None) -> dict[str, tuple[str, ...]]:
    """What node ``name`` of ``kind`` may do: its kind's interface (``_undeclared``'s when it
    declares none) with its launch file's ``remaps``, and every node's share."""
    i = interface_of(name, kind.interface, remaps)
    tokens = ROLES["teleop"]["token"] if kind.interface is None else ()
    return {
        "publish": (*i.publishes, PARAMETER_EVENTS, log_key(name)),  # its log records (runtime.log_stream)
        "subscribe": (*i.subscribes, CLOCK),  # a node started with use_sim_time follows the clock
        "serve": (
            *i.serves,
            params_key(name),
            param_describe_key(name),
            param_set_key(name),
            node_key(name),
            log_level_key(name),
            type_key("*", name),  # the description of each message type it uses
            log_key(name),  # its recent log records
        ),
        # `param list`, `param set` and the tools learning a type ask every node at once
        "asked": (params_key("*"), node_key("*"), type_key("*", "*"), LOG_KEYS),
        # `turtlectl log` (turtlectl/log/*), `record -a` and `foxglove` (**) subscribe on wildcards;
        # who subscribes to what the graph shows every node anyway (its entity tokens)
        "heard": ("**",),
        "call": i.calls,
        "token": (
            f"{NODE_TOKEN_PREFIX}/{name_chunk(name)}/**",
            f"{ENTITY_TOKEN_PREFIX}/{name_chunk(name)}/**",
            *tokens,
        ),
        # the claim check asks which entities exist; the navigator follows its callers' tokens
        "watch": (f"{ENTITY_TOKEN_PREFIX}/**", *i.watches),
    }


def launch_goal_services(kinds: dict[str, NodeKind], remaps: dict[str, dict[str, str]]) -> list[str]:
    """The goal services the nodes ``kinds`` (name -> kind) serve, each in its namespace with
    its launch file's ``remaps`` (roles.goal_services of its interface): what the roles that
    send goals may call, with each one's ``/cancel`` (``client_rights``)."""
    keys = [
        key
        for name, kind in kinds.items()
        for key in goal_services(interface_of(name, kind.interface, remaps.get(name)))
    ]
    return list(dict.fromkeys(keys))


def access_control(
    users: dict[str, dict[str, tuple[str, ...]]], domain: str = "", common_names: list[str] | None = None
) -> dict[str, Any]:
    """The router's ``access_control`` section: deny by default; each user (a login name) may
    do what its rights name (verb -> key expressions), in ``domain`` if given; with
    ``common_names`` (a TLS system), only over a link whose certificate bears one of them (a host
    left out is shut out: whatever its login, nothing it sends or is sent passes)."""
    prefix = f"{domain}/" if domain else ""
    rules, subjects, policies = [], [], []
    for user, rights in users.items():
        subject: dict[str, Any] = {"id": user, "usernames": [user]}
        if common_names is not None:
            subject["cert_common_names"] = list(common_names)
        subjects.append(subject)
        ids = []
        for verb, keys in rights.items():
            if not keys:
                continue
            for message, flow in VERBS[verb]:
                rule = f"{user}:{verb}:{message}:{flow}"
                rules.append(
                    {
                        "id": rule,
                        "messages": [message],
                        "flows": [flow],
                        "permission": "allow",
                        "key_exprs": [prefix + k for k in keys],
                    }
                )
                ids.append(rule)
        policies.append({"rules": ids, "subjects": [user]})
    return {
        "enabled": True,
        "default_permission": "deny",
        "rules": rules,
        "subjects": subjects,
        "policies": policies,
    }
