"""cli.tools.graph: the live graph built from liveliness tokens, and how it is shown."""

from turtlectl.cli.tools.graph import build_graph, graph_text
from turtlectl.messages.keys import (
    EntityInfo,
    NodeInfo,
    domain_token,
    entity_token,
    node_token,
)


def test_graph_from_tokens():
    keys = [
        node_token(NodeInfo(name="sim", pid=1, host="h", start_ns=1_000_000_000)),
        node_token(NodeInfo(name="navigator", pid=2, host="h", start_ns=2_000_000_000)),
        entity_token(EntityInfo(node="sim", pid=1, role="pub", type_name="Pose", key="turtle1/pose")),
        entity_token(EntityInfo(node="navigator", pid=2, role="sub", type_name="Pose", key="turtle1/pose")),
        entity_token(EntityInfo(node="navigator", pid=2, role="srv", type_name="NavigateToRequest", key="navigate_to")),
        "@turtlectl/client/123-abc",
    ]
    graph = build_graph(keys, now_ns=5_000_000_000)
    assert [(n.name, n.uptime) for n in graph.nodes] == [("navigator", 3.0), ("sim", 4.0)]
    (topic,) = graph.topics
    assert (topic.key, topic.type, topic.publishers, topic.subscribers) == (
        "turtle1/pose",
        "Pose",
        ["sim"],
        ["navigator"],
    )
    assert [(s.key, s.servers) for s in graph.services] == [("navigate_to", ["navigator"])]


def test_a_client_without_domain_sees_each_domain_prefixed():
    keys = [
        "lab1/" + node_token(NodeInfo(name="sim", pid=1, host="h", start_ns=1)),
        "lab1/" + entity_token(EntityInfo(node="sim", pid=1, role="pub", type_name="Pose", key="turtle1/pose")),
        "lab1/"
        + entity_token(
            EntityInfo(node="navigator", pid=2, role="srv", type_name="NavigateToRequest", key="navigate_to")
        ),
        node_token(NodeInfo(name="sim", pid=3, host="h", start_ns=1)),
        domain_token("lab1"),
        domain_token("lab2"),
    ]
    graph = build_graph(keys, now_ns=2)
    assert [(n.name, n.domain) for n in graph.nodes] == [("lab1:sim", "lab1"), ("sim", "")]
    assert [(t.key, t.publishers) for t in graph.topics] == [("lab1/turtle1/pose", ["lab1:sim"])]
    assert [(s.key, s.servers) for s in graph.services] == [("lab1/navigate_to", ["lab1:navigator"])]
    assert graph.domains == ["lab1", "lab2"]
    text = graph_text(graph)
    assert "lab1:sim" in text and "DOMAINS" in text and "lab1, lab2" in text


def test_an_empty_graph_says_what_to_do():
    graph = build_graph([], now_ns=0)
    graph.hint = "systems run in domain lab1 on this router: add it before the command, `turtlectl --domain lab1 ...`"
    assert (
        "(none: systems run in domain lab1 on this router: add it before the command, `turtlectl --domain lab1 ...`)"
        in graph_text(graph)
    )


def test_list_counts_the_services_every_node_has_instead_of_listing_them():
    """Issue 13: parameters, node info and log level are served by every node: listed with --all."""
    from turtlectl.cli.tools.graph import Graph, ServiceRow, without_node_services

    keys = [
        "navigate_to",
        "turtlectl/world",
        "turtlectl/params/sim",
        "turtlectl/params/sim/set",
        "turtlectl/nodes/sim",
        "turtlectl/nodes/sim/log_level",
        "lab1/turtlectl/params/sim",
    ]
    graph = Graph(nodes=[], topics=[], services=[ServiceRow(key=k, type="JSON", servers=["sim"]) for k in keys])
    kept = without_node_services(graph)
    assert [s.key for s in kept.services] == ["navigate_to", "turtlectl/world"] and kept.hidden_services == 5
    assert "(+ 5 services every node has: parameters, node info, log level; --all lists them)" in graph_text(kept)
