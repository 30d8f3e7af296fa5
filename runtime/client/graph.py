"""The live graph (nodes, topics, services) from liveliness token keys (pure: no zenoh).

A client without --domain also sees the systems that run in domains: their tokens are
``<domain>/@turtlectl/...``, and their nodes, topics and services are listed with the
domain in front (``lab1:sim`` for a node, ``lab1/robot/status`` for a key: the key such a client uses).
"""

from __future__ import annotations

import msgspec

from turtlectl.messages.keys import (
    CLIENT_ENTITY_TOKEN_PREFIX,
    FIRST_TURTLE,
    LOG,
    ClientInfo,
    EntityInfo,
    NodeInfo,
    namespace_of,
    parse_client_node_token,
    parse_domain_token,
    parse_entity_token,
    parse_node_token,
)


class NodeRow(msgspec.Struct):
    name: str  # its full name (turtle2/navigator: in namespace turtle2), with its domain in front (lab1:sim) when listed from outside the domain
    pid: int
    host: str
    uptime: float  # s
    domain: str = ""
    namespace: str = ""  # turtle2 for turtle2/navigator (lab1:turtle2/navigator too); "" outside any
    tool: str = ""  # a client's tool (teleop, goto, echo, record, plot, ...; python: a script's Client); "" for a node


class TopicRow(msgspec.Struct):
    key: str
    type: str
    publishers: list[str]
    subscribers: list[str]


class ServiceRow(msgspec.Struct):
    key: str
    type: str  # the request type
    servers: list[str]


class GoalRow(msgspec.Struct):
    key: str
    goal: str  # the goal's type
    feedback: str  # its feedback's
    result: str  # its result's
    servers: list[str]


class Graph(msgspec.Struct):
    nodes: list[NodeRow]
    topics: list[TopicRow]
    services: list[ServiceRow]
    domains: list[str] = msgspec.field(default_factory=list)  # with a system on this router (seen from outside)
    hint: str = ""  # what to do when there are no nodes (e.g. "add --domain lab1")
    hidden_services: int = 0  # each node's own services left out (``list`` without --all)
    hidden_topics: int = 0  # each node's own log topic left out (``list`` without --all)
    conflicts: list[str] = msgspec.field(default_factory=list)  # a type name two nodes describe differently
    goals: list[GoalRow] = msgspec.field(default_factory=list)  # the goal services (``turtlectl action list``)
    #: the clients (command-line tools, scripts' Clients) with a session open, but the one asking
    clients: list[NodeRow] = msgspec.field(default_factory=list)


#: a goal service's token roles -> the GoalRow field each names
GOAL_FIELDS = {"goal": "goal", "goal_feedback": "feedback", "goal_result": "result"}

#: where the services every node has live (parameters, node info, log level)
NODE_SERVICE_ROOTS = ("turtlectl/params/", "turtlectl/nodes/")
#: where the topics every node has live (its log: ``turtlectl/log/<node>``)
NODE_TOPIC_ROOTS = (f"{LOG}/",)


def under(key: str, roots: tuple[str, ...] = ("turtlectl/",)) -> bool:
    """Whether ``key`` lies under one of ``roots``, in any domain (default: the runtime's own
    keys, every node's: parameters, node info, parameter events, type descriptions)."""
    in_domain = key.partition("/")[2]  # lab1/turtlectl/params/sim seen from outside lab1
    return any(key.startswith(root) or in_domain.startswith(root) for root in roots)


def without_node_services(graph: Graph) -> Graph:
    """``graph`` without the services every node has (``turtlectl/params/<node>``,
    ``turtlectl/nodes/<node>`` and below, in any domain), counted in ``hidden_services``, nor
    the log topic every node has (``turtlectl/log/<node>``), counted in ``hidden_topics``."""
    kept = [s for s in graph.services if not under(s.key, NODE_SERVICE_ROOTS)]
    topics = [t for t in graph.topics if not under(t.key, NODE_TOPIC_ROOTS)]
    return msgspec.structs.replace(
        graph,
        services=kept,
        hidden_services=len(graph.services) - len(kept),
        topics=topics,
        hidden_topics=len(graph.topics) - len(topics),
    )


def _in_domain(prefix: str, name: str) -> str:
    """A node's name seen from outside its domain: ``lab1:sim`` (``lab1:turtle2/navigator``:
    a ``/`` in a name is its namespace's)."""
    return f"{prefix[:-1]}:{name}" if prefix else name


def _split_domain(key: str) -> tuple[str, str]:
    """(``lab1/``, ``@turtlectl/...``) for a token declared in domain lab1, ("", key) otherwise."""
    head, slash, rest = key.partition("/")
    if slash and not head.startswith("@") and rest.startswith("@turtlectl/"):
        return head + "/", rest
    return "", key


def build_graph(keys: list[str], now_ns: int) -> Graph:
    """The graph described by liveliness ``keys``, with uptimes as of ``now_ns`` (wall clock, ns)."""
    nodes: list[tuple[str, NodeInfo]] = []
    clients: list[tuple[str, NodeInfo]] = []
    entities: list[EntityInfo] = []
    domains: set[str] = set()
    for full_key in keys:
        prefix, key = _split_domain(full_key)
        if prefix:
            domains.add(prefix[:-1])
        if (domain := parse_domain_token(key)) is not None:
            domains.add(domain)
            continue
        node = parse_node_token(key)
        if node is not None:
            nodes.append((prefix, msgspec.structs.replace(node, name=_in_domain(prefix, node.name))))
            continue
        client = parse_client_node_token(key)
        if client is not None:
            clients.append((prefix, msgspec.structs.replace(client, name=_in_domain(prefix, client.name))))
            continue
        entity = parse_entity_token(key) or parse_entity_token(key, CLIENT_ENTITY_TOKEN_PREFIX)
        if entity is not None:
            entities.append(
                msgspec.structs.replace(entity, node=_in_domain(prefix, entity.node), key=prefix + entity.key)
            )
    topics: dict[str, TopicRow] = {}
    services: dict[str, ServiceRow] = {}
    goals: dict[str, GoalRow] = {}
    for e in sorted(entities, key=lambda e: (e.key, e.node)):
        if e.role in GOAL_FIELDS:
            goal = goals.setdefault(e.key, GoalRow(key=e.key, goal="", feedback="", result="", servers=[]))
            setattr(goal, GOAL_FIELDS[e.role], e.type_name)
            if e.role == "goal":
                goal.servers.append(e.node)
        elif e.role == "srv":
            row = services.setdefault(e.key, ServiceRow(key=e.key, type=e.type_name, servers=[]))
            row.servers.append(e.node)
        else:
            topic = topics.setdefault(e.key, TopicRow(key=e.key, type=e.type_name, publishers=[], subscribers=[]))
            (topic.publishers if e.role == "pub" else topic.subscribers).append(e.node)
    return Graph(
        nodes=[_row(prefix, n, now_ns) for prefix, n in sorted(nodes, key=lambda pn: pn[1].name)],
        topics=list(topics.values()),
        services=list(services.values()),
        domains=sorted(domains),
        goals=list(goals.values()),
        clients=[_row(prefix, c, now_ns) for prefix, c in sorted(clients, key=lambda pc: pc[1].name)],
    )


def _row(prefix: str, n: NodeInfo, now_ns: int) -> NodeRow:
    return NodeRow(
        name=n.name,
        pid=n.pid,
        host=n.host,
        uptime=max(0.0, (now_ns - n.start_ns) / 1e9) if n.start_ns else 0.0,
        domain=prefix[:-1],
        namespace="" if isinstance(n, ClientInfo) else namespace_of(n.name.partition(":")[2] if prefix else n.name),
        tool=n.tool if isinstance(n, ClientInfo) else "",
    )


def without_client(graph: Graph, name: str) -> Graph:
    """``graph`` without client ``name`` and its publishers and subscribers (the one asking)."""

    def ends(names: list[str]) -> list[str]:
        return [n for n in names if n != name]

    return msgspec.structs.replace(
        graph,
        clients=[c for c in graph.clients if c.name != name],
        topics=[
            msgspec.structs.replace(t, publishers=ends(t.publishers), subscribers=ends(t.subscribers))
            for t in graph.topics
            if ends(t.publishers) or ends(t.subscribers)
        ],
    )


PUB_WIDTH = 40  # characters: the widest the TOPICS table's publishers column gets


def _width(values: list[str], least: int) -> int:
    return max([least, *map(len, values)])


def _namespace(node: NodeRow) -> str:
    """``node``'s namespace, from its name (rows built elsewhere may leave ``namespace`` empty)."""
    return node.namespace or namespace_of(node.name.partition(":")[2] if node.domain else node.name)


def _node_lines(nodes: list[NodeRow]) -> list[str]:
    """One line per node; grouped by turtle when any node runs in a namespace: a heading per
    namespace (``turtle2``; ``lab1:turtle2`` in domain lab1), the nodes outside any under
    ``turtle1 (no namespace)``, each group's nodes indented below its heading."""
    name_w = _width([n.name for n in nodes], 20)
    host_w = _width([n.host for n in nodes], 8)

    def line(n: NodeRow, indent: str) -> str:
        return f"{indent}{n.name:{name_w}s} pid {n.pid:<8d} host {n.host:{host_w}s} up {n.uptime:8.1f} s"

    if not any(_namespace(n) for n in nodes):
        return [line(n, "  ") for n in nodes]
    groups: dict[tuple[str, str], list[NodeRow]] = {}
    for n in nodes:
        groups.setdefault((n.domain, _namespace(n)), []).append(n)
    lines = []
    for domain, namespace in sorted(groups, key=lambda g: (g[0], g[1] != "", g[1])):
        heading = namespace or f"{FIRST_TURTLE} (no namespace)"
        lines.append(f"  {domain}:{heading}" if domain else f"  {heading}")
        lines += [line(n, "    ") for n in groups[domain, namespace]]
    return lines


def client_lines(clients: list[NodeRow]) -> list[str]:
    """One line per client: its name, tool, pid, host and uptime, aligned."""
    name_w = _width([c.name for c in clients], 20)
    tool_w = _width([c.tool for c in clients], 6)
    host_w = _width([c.host for c in clients], 8)
    return [
        f"  {c.name:{name_w}s} {c.tool:{tool_w}s} pid {c.pid:<8d} host {c.host:{host_w}s} up {c.uptime:8.1f} s"
        for c in clients
    ]


def graph_text(graph: Graph) -> str:
    """The graph as aligned tables for people (columns as wide as their longest entry)."""
    lines = ["NODES"]
    lines += _node_lines(graph.nodes) or [f"  (none{': ' + graph.hint if graph.hint else ''})"]
    if graph.clients:
        lines.append("CLIENTS (command-line tools and scripts with a session open)")
        lines += client_lines(graph.clients)
    lines.append("TOPICS")
    key_w = _width([t.key for t in graph.topics], 22)
    type_w = _width([t.type for t in graph.topics], 12)
    # at most PUB_WIDTH wide: one long list (every node publishes parameter events) widens only its own line
    pub_w = min(PUB_WIDTH, _width([", ".join(t.publishers) or "-" for t in graph.topics], 10))
    for t in graph.topics:
        pubs = ", ".join(t.publishers) or "-"
        lines.append(
            f"  {t.key:{key_w}s} {t.type:{type_w}s} pub: {pubs:{pub_w}s} sub: {', '.join(t.subscribers) or '-'}"
        )
    if not graph.topics:
        lines.append("  (none)")
    if graph.hidden_topics:
        lines.append(
            f"  (+ {graph.hidden_topics} log topics, one per node: `turtlectl log` reads them; --all lists them)"
        )
    lines.append("SERVICES")
    key_w = _width([s.key for s in graph.services], 28)
    type_w = _width([s.type for s in graph.services], 12)
    lines += [f"  {s.key:{key_w}s} {s.type:{type_w}s} served by {', '.join(s.servers)}" for s in graph.services] or [
        "  (none)"
    ]
    if graph.hidden_services:
        lines.append(
            f"  (+ {graph.hidden_services} services every node has: parameters, node info, log level; --all lists them)"
        )
    if graph.domains:
        lines.append(
            f"DOMAINS (their nodes and keys are listed with the domain in front)\n  {', '.join(graph.domains)}"
        )
    if graph.conflicts:
        lines += ["CONFLICTS (one type name, two types: rename one)"] + [f"  {c}" for c in graph.conflicts]
    return "\n".join(lines)


def clients_publishing(graph: Graph, key: str) -> list[NodeRow]:
    """The clients that publish on ``key`` (two teleops, a ``pub`` and a teleop on one
    ``cmd_vel`` would both drive the turtle); a publisher whose client is not listed yet gets
    a row with its pid only."""
    names = next((t.publishers for t in graph.topics if t.key == key), [])
    rows = {c.name: c for c in graph.clients}
    nodes = {n.name for n in graph.nodes}
    return [rows.get(name) or NodeRow(name=name, pid=0, host="", uptime=0.0) for name in names if name not in nodes]


def who(client: NodeRow) -> str:
    """``teleop-4242 (pid 4242, host lab-pc)``: a client as a message names it."""
    where = f"pid {client.pid}" + (f", host {client.host}" if client.host else "")
    return f"{client.name} ({where})"
