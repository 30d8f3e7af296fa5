"""runtime.client.graph: the live graph built from liveliness tokens, and how it is shown."""

from turtlectl.messages.keys import (
    EntityInfo,
    NodeInfo,
    domain_token,
    entity_token,
    node_token,
)
from turtlectl.runtime.client.graph import build_graph, graph_text


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
    """Parameters, node info and log level are served by every node: listed with --all."""
    from turtlectl.runtime.client.graph import Graph, ServiceRow, without_node_services

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


def _fleet_keys(prefix: str = "") -> list[str]:
    names = ["sim", "navigator", "turtle2/navigator", "turtle2/status_monitor", "turtle3/navigator"]
    return [prefix + node_token(NodeInfo(name=n, pid=i, host="h", start_ns=1)) for i, n in enumerate(names)]


def test_list_groups_the_nodes_by_turtle_when_namespaces_run():
    """A heading per namespace, turtle1's nodes (outside any) first, each group indented."""
    graph = build_graph(_fleet_keys(), now_ns=1)
    assert [(n.name, n.namespace) for n in graph.nodes] == [
        ("navigator", ""),
        ("sim", ""),
        ("turtle2/navigator", "turtle2"),
        ("turtle2/status_monitor", "turtle2"),
        ("turtle3/navigator", "turtle3"),
    ]
    nodes = graph_text(graph).split("TOPICS")[0].splitlines()[1:]
    assert [line.split()[0] for line in nodes] == [
        "turtle1",
        "navigator",
        "sim",
        "turtle2",
        "turtle2/navigator",
        "turtle2/status_monitor",
        "turtle3",
        "turtle3/navigator",
    ]
    assert nodes[0] == "  turtle1 (no namespace)" and nodes[3] == "  turtle2" and nodes[6] == "  turtle3"
    assert nodes[1].startswith("    navigator ") and nodes[4].startswith("    turtle2/navigator ")


def test_list_keeps_the_flat_layout_without_namespaces_and_groups_a_domains_turtles():
    flat = build_graph(_fleet_keys()[:2], now_ns=1)
    assert graph_text(flat).splitlines()[1:3] == [
        "  navigator            pid 1        host h        up      0.0 s",
        "  sim                  pid 0        host h        up      0.0 s",
    ]
    graph = build_graph(_fleet_keys("lab1/")[:3] + [node_token(NodeInfo(name="sim", pid=9, host="h", start_ns=1))], 1)
    assert [(n.name, n.domain, n.namespace) for n in graph.nodes] == [
        ("lab1:navigator", "lab1", ""),
        ("lab1:sim", "lab1", ""),
        ("lab1:turtle2/navigator", "lab1", "turtle2"),
        ("sim", "", ""),
    ]
    nodes = graph_text(graph).split("TOPICS")[0].splitlines()[1:]
    headings = [line.strip() for line in nodes if not line.startswith("    ")]
    assert headings == ["turtle1 (no namespace)", "lab1:turtle1 (no namespace)", "lab1:turtle2"]


def test_one_long_publisher_list_widens_only_its_own_line():
    from turtlectl.runtime.client.graph import Graph, TopicRow

    many = [f"turtle{i}/navigator" for i in range(2, 12)]
    graph = Graph(
        nodes=[],
        services=[],
        topics=[
            TopicRow(key="turtle1/pose", type="Pose", publishers=["sim"], subscribers=["navigator"]),
            TopicRow(key="turtlectl/parameter_events", type="ParameterEvent", publishers=many, subscribers=[]),
        ],
    )
    pose_line = next(line for line in graph_text(graph).splitlines() if "turtle1/pose" in line)
    assert len(pose_line) < 120 and pose_line.endswith("sub: navigator")


def test_list_counts_the_log_topic_every_node_has_instead_of_listing_it():
    """Every node publishes its log on turtlectl/log/<node>: listed with --all."""
    from turtlectl.runtime.client.graph import Graph, TopicRow, without_node_services

    keys = ["robot/status", "turtlectl/parameter_events", "turtlectl/log/sim", "turtlectl/log/turtle2.navigator"]
    graph = Graph(
        nodes=[], topics=[TopicRow(key=k, type="Log", publishers=["sim"], subscribers=[]) for k in keys], services=[]
    )
    kept = without_node_services(graph)
    assert [t.key for t in kept.topics] == ["robot/status", "turtlectl/parameter_events"] and kept.hidden_topics == 2
    assert "(+ 2 log topics, one per node: `turtlectl log` reads them; --all lists them)" in graph_text(kept)
    assert "log topics" not in graph_text(graph)


def _clients_graph():
    from turtlectl.messages.keys import ClientInfo, client_entity_token, client_node_token

    return build_graph(
        [
            node_token(NodeInfo(name="sim", pid=1, host="h", start_ns=1_000_000_000)),
            entity_token(EntityInfo(node="sim", pid=1, role="sub", type_name="turtlectl/Twist", key="turtle1/cmd_vel")),
            client_node_token(ClientInfo(name="teleop-42", pid=42, host="lab", start_ns=4_000_000_000, tool="teleop")),
            client_entity_token(
                EntityInfo(node="teleop-42", pid=42, role="pub", type_name="turtlectl/Twist", key="turtle1/cmd_vel")
            ),
            client_node_token(ClientInfo(name="echo-7", pid=7, host="pc", start_ns=3_000_000_000, tool="echo")),
            "lab1/"
            + client_node_token(ClientInfo(name="python-9", pid=9, host="pc", start_ns=3_000_000_000, tool="python")),
        ],
        now_ns=5_000_000_000,
    )


def test_clients_are_listed_apart_from_the_nodes_with_tool_pid_host_and_their_publishers():
    graph = _clients_graph()
    assert [n.name for n in graph.nodes] == ["sim"]
    assert [(c.name, c.tool, c.pid, c.host, c.uptime, c.domain) for c in graph.clients] == [
        ("echo-7", "echo", 7, "pc", 2.0, ""),
        ("lab1:python-9", "python", 9, "pc", 2.0, "lab1"),
        ("teleop-42", "teleop", 42, "lab", 1.0, ""),
    ]
    (topic,) = graph.topics
    assert (topic.publishers, topic.subscribers) == (["teleop-42"], ["sim"])
    text = graph_text(graph)
    assert "CLIENTS" in text and "teleop-42" in text.split("CLIENTS")[1].split("TOPICS")[0]
    assert "teleop-42            teleop pid 42       host lab      up      1.0 s" in text


def test_the_one_asking_is_left_out_and_the_clients_driving_a_turtle_are_found():
    from turtlectl.runtime.client.graph import clients_publishing, who, without_client

    graph = _clients_graph()
    (driver,) = clients_publishing(graph, "turtle1/cmd_vel")
    assert who(driver) == "teleop-42 (pid 42, host lab)"
    assert clients_publishing(graph, "turtle1/pose") == []
    mine = without_client(graph, "teleop-42")
    assert "teleop-42" not in [c.name for c in mine.clients]
    assert clients_publishing(mine, "turtle1/cmd_vel") == [] and mine.topics[0].subscribers == ["sim"]
