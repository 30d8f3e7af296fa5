"""cli.system.access: the rules of a --secure router (deny by default) and the clients' own check."""

from __future__ import annotations

import zenoh

from turtlectl.cli.system.access import ROLES, access_control, node_rights
from turtlectl.messages.keys import LOG_KEYS, log_key
from turtlectl.nodes.kinds import KINDS
from turtlectl.runtime.client.session import permitted, who_may


def test_roles_grow_viewer_operator_teleop():
    assert permitted("viewer", "subscribe", "robot/status") and not permitted("viewer", "call", "navigate_to")
    assert permitted("operator", "call", "navigate_to") and permitted("operator", "call", "turtlectl/params/sim/set")
    assert not permitted("operator", "publish", "turtle1/cmd_vel") and permitted("teleop", "publish", "turtle1/cmd_vel")
    assert who_may("call", "reset") == ["operator", "teleop"] and not permitted("nobody", "call", "reset")


def test_each_node_may_do_what_its_kind_declares_and_no_more():
    sim = node_rights("sim", KINDS["sim"])
    # every turtle's keys (spawn), turtle1's among them
    assert "*/cmd_vel" in sim["subscribe"] and "*/pose" in sim["publish"] and "spawn" in sim["serve"]
    assert "*/cmd_vel" not in sim["publish"] and "navigate_to" not in sim["serve"]
    nav = node_rights("navigator", KINDS["navigator"])
    assert "navigate_to" in nav["serve"] and "turtle1/cmd_vel" in nav["publish"]
    assert "turtlectl/params/navigator/set" in nav["serve"] and "turtlectl/params/sim/set" not in nav["serve"]


def test_the_router_section_denies_by_default_and_allows_per_user_in_the_domain():
    section = access_control({"node-sim": node_rights("sim", KINDS["sim"]), "viewer": ROLES["viewer"]}, domain="lab1")
    assert section["enabled"] is True and section["default_permission"] == "deny"
    assert {s["id"]: s["usernames"] for s in section["subjects"]} == {"node-sim": ["node-sim"], "viewer": ["viewer"]}
    rules = {r["id"]: r for r in section["rules"]}
    put = rules["node-sim:publish:put:ingress"]
    assert put["permission"] == "allow" and "lab1/*/pose" in put["key_exprs"]  # every turtle's
    assert all(
        r["permission"] == "allow" and all(k.startswith("lab1/") for k in r["key_exprs"]) for r in rules.values()
    )
    policy = {p["subjects"][0]: set(p["rules"]) for p in section["policies"]}
    assert all(rule.startswith("viewer:") for rule in policy["viewer"])


def test_the_role_check_reads_a_domain_s_key_from_outside_it_and_roles_are_named(monkeypatch, tmp_path):
    """`call lab1/navigate_to` as operator is not "not permitted (may: no client role)"; an unknown
    TURTLECTL_ROLE does not look like a missing login, nor a corrupt credentials file like an empty one."""
    import pytest

    from turtlectl.runtime.client import credentials
    from turtlectl.runtime.client import session as client
    from turtlectl.runtime.client.errors import BadInput

    client.check_permitted("operator", "call", "lab1/navigate_to", domain="")
    with pytest.raises(client.NotPermitted, match=r"may not publish lab1/turtle1/cmd_vel .*\(may: teleop;"):
        client.check_permitted("operator", "publish", "lab1/turtle1/cmd_vel", domain="")
    monkeypatch.setenv(credentials.ROLE_ENV, "Viewer")
    with pytest.raises(BadInput, match=r"TURTLECTL_ROLE='Viewer' is not a role \(roles: viewer, operator, teleop\)"):
        credentials.role()
    broken = tmp_path / "credentials.json"
    broken.write_text("{not json")
    with pytest.raises(BadInput, match="is not one turtlectl wrote"):
        credentials.for_endpoint("tcp/127.0.0.1:7447", broken, as_role="operator")
    with pytest.raises(BadInput):
        credentials.publish("tcp/127.0.0.1:7447", {}, broken)
    assert broken.read_text() == "{not json"  # never overwritten


def test_every_node_serves_the_description_of_its_parameters_and_a_viewer_may_read_it():
    """`param describe` and `param set` ask turtlectl/params/<node>/describe."""
    assert "turtlectl/params/navigator/describe" in node_rights("navigator", KINDS["navigator"])["serve"]
    assert permitted("viewer", "call", "turtlectl/params/navigator/describe")


def test_a_user_kind_without_an_interface_may_do_what_teleop_may_and_use_its_own_name():
    from turtlectl.nodes.kinds import Interface, NodeKind
    from turtlectl.sim.params import SimParams

    mine = node_rights("guard", NodeKind("/p/patrol.py:Patrol", SimParams))
    # what teleop may: drive any turtle, turtle1 among them
    assert "*/cmd_vel" in mine["publish"] and "guard/**" in mine["publish"] and mine["serve"][0] == "guard/**"
    assert mine["subscribe"] == ("**", "clock") and "navigate_to" in mine["call"]
    declared = node_rights("guard", NodeKind("/p/patrol.py:Patrol", SimParams, interface=Interface(publishes=("a",))))
    assert declared["publish"][0] == "a"
    # every node's share: the simulator's clock (use_sim_time)
    assert declared["subscribe"] == ("clock",) and "turtle1/cmd_vel" not in declared["publish"]


def test_every_node_may_publish_and_serve_its_own_log_and_a_viewer_may_read_every_nodes():
    """One log stream.  Zenoh drops a denied put without a word: a node's log key is
    its own share under --secure, whatever its kind declares, and no other node's."""
    for name, kind in (("navigator", KINDS["navigator"]), ("turtle2/navigator", KINDS["navigator"])):
        rights = node_rights(name, kind)
        key = log_key(name)
        assert key in rights["publish"] and key in rights["serve"] and LOG_KEYS in rights["asked"]
        # a publisher hears of a wildcard subscriber (turtlectl log's, record -a's) only through a rule as wide
        assert rights["heard"] == ("**",)
    assert "turtlectl/log/sim" not in node_rights("navigator", KINDS["navigator"])["publish"]
    assert "turtlectl/log/turtle2.navigator" in node_rights("turtle2/navigator", KINDS["navigator"])["publish"]
    assert permitted("viewer", "subscribe", "turtlectl/log/navigator") and permitted("viewer", "call", LOG_KEYS)


def test_an_operator_may_send_goals_to_and_cancel_every_goal_service_the_launch_serves_a_viewer_none():
    """A user's goal service (a patrol's laps, a declared or an undeclared interface) is the
    operator's as navigate_to is: KEY and KEY/cancel on the router; a viewer may call neither."""
    from turtlectl.cli.system.access import client_rights, launch_goal_services
    from turtlectl.nodes.kinds import NodeKind
    from turtlectl.runtime.config import Interface

    declared = Interface(serves=("arm/laps", "arm/laps/cancel", "arm/stop"), publishes=("arm/laps/feedback",))
    kinds = {
        "sim": KINDS["sim"],
        "navigator": KINDS["navigator"],
        "turtle2/navigator": KINDS["navigator"],
        "arm": NodeKind("./arm.py:Arm", KINDS["navigator"].params, (), declared),
        "patrol": NodeKind("./patrol.py:Patrol", KINDS["navigator"].params, (), None),
    }
    goals = launch_goal_services(kinds, {})
    assert goals == ["navigate_to", "turtle2/navigate_to", "arm/laps", "patrol/**"]
    operator, viewer = client_rights("operator", goals), client_rights("viewer", goals)
    for key in ("arm/laps", "arm/laps/cancel", "patrol/laps", "patrol/laps/cancel", "turtle2/navigate_to/cancel"):
        assert any(zenoh.KeyExpr(k).includes(zenoh.KeyExpr(key)) for k in operator["call"]), key
        assert not any(zenoh.KeyExpr(k).includes(zenoh.KeyExpr(key)) for k in viewer["call"]), key
    assert client_rights("teleop", goals)["call"] == operator["call"]
    assert not any(zenoh.KeyExpr(k).includes(zenoh.KeyExpr("arm/stop")) for k in operator["call"])  # goals only
    # the clients' own check: a key the graph shows as a goal service
    assert permitted("operator", "call", "arm/laps", goal_service=True)
    assert not permitted("operator", "call", "arm/laps")  # not known as one: the role's table
    assert not permitted("viewer", "call", "arm/laps/cancel", goal_service=True)
    assert who_may("call", "arm/laps", goal_service=True) == ["operator", "teleop"]


def test_every_role_may_declare_its_presence_in_the_graph_and_no_node_s_tokens():
    from turtlectl.messages.keys import (
        ClientInfo,
        EntityInfo,
        NodeInfo,
        client_entity_token,
        client_node_token,
        node_token,
    )

    me = client_node_token(ClientInfo(name="echo-7", pid=7, host="h", start_ns=1, tool="echo"))
    sub = client_entity_token(EntityInfo(node="echo-7", pid=7, role="sub", type_name="T", key="robot/status"))
    for role in ROLES:
        assert permitted(role, "token", me) and permitted(role, "token", sub), role
        assert not permitted(role, "token", node_token(NodeInfo(name="sim", pid=1))), role
    rules = access_control({"viewer": ROLES["viewer"]})["rules"]
    assert any(r["messages"] == ["liveliness_token"] and "@turtlectl/client_node/**" in r["key_exprs"] for r in rules)
