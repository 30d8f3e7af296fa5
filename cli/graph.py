"""The live graph (nodes, topics, services) from liveliness token keys (pure: no zenoh)."""

from __future__ import annotations

import msgspec

from messages.keys import EntityInfo, NodeInfo, parse_entity_token, parse_node_token


class NodeRow(msgspec.Struct):
    name: str
    pid: int
    host: str
    uptime: float  # s


class TopicRow(msgspec.Struct):
    key: str
    type: str
    publishers: list[str]
    subscribers: list[str]


class ServiceRow(msgspec.Struct):
    key: str
    type: str  # the request type
    servers: list[str]


class Graph(msgspec.Struct):
    nodes: list[NodeRow]
    topics: list[TopicRow]
    services: list[ServiceRow]


def build_graph(keys: list[str], now_ns: int) -> Graph:
    """The graph described by liveliness ``keys``, with uptimes as of ``now_ns`` (wall clock, ns)."""
    nodes: list[NodeInfo] = []
    entities: list[EntityInfo] = []
    for key in keys:
        node = parse_node_token(key)
        if node is not None:
            nodes.append(node)
            continue
        entity = parse_entity_token(key)
        if entity is not None:
            entities.append(entity)
    topics: dict[str, TopicRow] = {}
    services: dict[str, ServiceRow] = {}
    for e in sorted(entities, key=lambda e: (e.key, e.node)):
        if e.role == "srv":
            row = services.setdefault(e.key, ServiceRow(key=e.key, type=e.type_name, servers=[]))
            row.servers.append(e.node)
        else:
            topic = topics.setdefault(e.key, TopicRow(key=e.key, type=e.type_name, publishers=[], subscribers=[]))
            (topic.publishers if e.role == "pub" else topic.subscribers).append(e.node)
    return Graph(
        nodes=[
            NodeRow(name=n.name, pid=n.pid, host=n.host, uptime=max(0.0, (now_ns - n.start_ns) / 1e9) if n.start_ns else 0.0)
            for n in sorted(nodes, key=lambda n: n.name)
        ],
        topics=list(topics.values()),
        services=list(services.values()),
    )


def graph_text(graph: Graph) -> str:
    """The graph as aligned tables for people."""
    lines = ["NODES"]
    lines += [f"  {n.name:20s} pid {n.pid:<8d} host {n.host:16s} up {n.uptime:8.1f} s" for n in graph.nodes] or ["  (none)"]
    lines.append("TOPICS")
    for t in graph.topics:
        lines.append(f"  {t.key:22s} {t.type:20s} pub: {', '.join(t.publishers) or '-':20s} sub: {', '.join(t.subscribers) or '-'}")
    if not graph.topics:
        lines.append("  (none)")
    lines.append("SERVICES")
    lines += [f"  {s.key:28s} {s.type:18s} served by {', '.join(s.servers)}" for s in graph.services] or ["  (none)"]
    return "\n".join(lines)
