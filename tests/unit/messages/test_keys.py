"""messages.keys: every key has a type; node, entity, domain and client tokens round-trip."""

from turtlectl.messages import (
    NavigateToRequest,
    NavigateToResponse,
)
from turtlectl.messages.keys import (
    SERVICES,
    TOPICS,
    EntityInfo,
    NodeInfo,
    client_token,
    domain_token,
    entity_token,
    node_token,
    parse_domain_token,
    parse_entity_token,
    parse_node_token,
)


def test_every_key_has_a_message_type():
    assert set(TOPICS) == {
        "turtle1/cmd_vel",
        "turtle1/pose",
        "robot/status",
        "obstacles",
        "navigate_to/feedback",
        "turtlectl/parameter_events",
        "turtles",
        "clock",
    }
    assert SERVICES["navigate_to"] == (NavigateToRequest, NavigateToResponse)


def test_node_token_round_trip():
    info = NodeInfo(name="navigator", pid=42, host="box.local", start_ns=17)
    assert parse_node_token(node_token(info)) == info
    assert parse_node_token(node_token(NodeInfo(name="n", pid=1, host="we/ird*"))).host == "we_ird_"
    assert parse_node_token("@turtlectl/node/x") is None
    assert parse_node_token("@turtlectl/node/x/1/host/notanumber") is None
    assert parse_node_token("other/key") is None


def test_entity_token_round_trip_keeps_slashes_in_the_key():
    entity = EntityInfo(node="sim", pid=7, role="pub", type_name="Pose", key="turtle1/pose")
    assert parse_entity_token(entity_token(entity)) == entity
    assert parse_entity_token("@turtlectl/entity/sim/7/bad/Pose/k") is None


def test_domain_and_client_tokens():
    assert domain_token("lab1") == "@turtlectl/domain/lab1" and parse_domain_token("@turtlectl/domain/lab1") == "lab1"
    assert parse_domain_token("@turtlectl/domain/a/b") is None and parse_domain_token("@turtlectl/node/x") is None
    assert client_token("42-abcd") == "@turtlectl/client/42-abcd"


def test_a_client_s_presence_and_entities_round_trip_apart_from_the_nodes():
    from turtlectl.messages.keys import (
        CLIENT_ENTITY_TOKEN_PREFIX,
        ClientInfo,
        EntityInfo,
        client_entity_token,
        client_node_token,
        parse_client_node_token,
        parse_entity_token,
        parse_node_token,
    )

    info = ClientInfo(name="teleop-42", pid=42, host="lab pc", start_ns=7, tool="teleop")
    token = client_node_token(info)
    assert token == "@turtlectl/client_node/teleop-42/42/lab_pc/7/teleop"
    assert parse_client_node_token(token) == ClientInfo(
        name="teleop-42", pid=42, host="lab_pc", start_ns=7, tool="teleop"
    )
    assert parse_node_token(token) is None and parse_client_node_token("@turtlectl/node/sim/1/h/2") is None
    entity = EntityInfo(node="teleop-42", pid=42, role="pub", type_name="turtlectl/Twist", key="turtle2/cmd_vel")
    key = client_entity_token(entity)
    assert key == "@turtlectl/client_entity/teleop-42/42/pub/turtlectl.Twist/turtle2/cmd_vel"
    assert parse_entity_token(key) is None  # never a node's: a node's claims do not see it
    assert parse_entity_token(key, CLIENT_ENTITY_TOKEN_PREFIX) == entity
