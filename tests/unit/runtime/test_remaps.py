"""Launch composition: a node's ``remap`` (ROS's remappings) goes through the one key
resolution, messages.keys.resolve, so that the keys a node uses, the interface it may declare
(its access rules under --secure), its claims and what it announces all say the same key."""

from __future__ import annotations

import msgspec
import pytest

from turtlectl.cli.system.access import node_rights
from turtlectl.messages import Twist
from turtlectl.messages.keys import includes, key_problem, resolve
from turtlectl.nodes.kinds import KINDS
from turtlectl.runtime.config import Interface
from turtlectl.runtime.fake import FakeNode
from turtlectl.runtime.interface import OutsideInterface
from turtlectl.runtime.roles import claims_of, interface_of

SAFETY = {"turtle1/cmd_vel": "safety/cmd_vel"}


@pytest.mark.parametrize(
    "key, namespace, remaps, used",
    [
        ("turtle1/cmd_vel", "", SAFETY, "safety/cmd_vel"),
        ("turtle1/cmd_vel", "turtle2", SAFETY, "turtle2/safety/cmd_vel"),  # both sides resolved in the namespace
        ("turtle1/cmd_vel", "turtle2", {"/turtle2/cmd_vel": "/safety/cmd_vel"}, "safety/cmd_vel"),  # absolute
        ("turtle1/cmd_vel", "turtle2", {"turtle1/cmd_vel": "turtle1/cmd_vel_raw"}, "turtle2/cmd_vel_raw"),
        ("/turtles", "turtle2", {"turtles": "all_turtles"}, "turtle2/all_turtles"),  # world keys: never namespaced
        ("turtle1/pose", "turtle2", SAFETY, "turtle2/pose"),  # another key: unchanged
        ("turtle1/cmd_vel", "turtle2", {"turtle2/cmd_vel": "x"}, "turtle2/cmd_vel"),  # relative: turtle2/turtle2/...
        ("turtle1/cmd_vel", "", {}, "turtle1/cmd_vel"),
    ],
)
def test_a_remap_matches_the_key_as_the_node_writes_it_or_absolute_and_resolves_as_its_keys_do(
    key, namespace, remaps, used
):
    assert resolve(key, namespace, remaps) == used


def test_key_expressions_include_as_zenohs_do():
    assert includes("*/cmd_vel", "turtle1/cmd_vel") and not includes("*/cmd_vel", "a/b/cmd_vel")
    assert includes("**/navigate_to/cancel", "navigate_to/cancel") and includes("a/**", "a")
    assert includes("**", "turtle2/safety/cmd_vel") and not includes("turtle1/pose", "turtle1/cmd_vel")
    assert key_problem("turtle2/safety/cmd_vel") is None and key_problem("/cmd_vel") is None
    assert all(key_problem(k) for k in ("a//b", "*/cmd_vel", "a/", "", "@turtlectl/x", "a b"))


def test_the_navigators_interface_and_claims_say_the_remapped_key():
    navigator = KINDS["navigator"]
    remaps = {"turtle1/cmd_vel": "safety/cmd_vel", "navigate_to": "nav/go"}
    i = interface_of("turtle2/navigator", navigator.interface, remaps)
    assert "turtle2/safety/cmd_vel" in i.publishes and "turtle2/cmd_vel" not in i.publishes
    assert "turtle2/nav/go" in i.serves and "turtle2/navigate_to" not in i.serves
    assert claims_of("turtle2/navigator", navigator.claims, remaps)[0].key == "turtle2/nav/go"
    rights = node_rights("turtle2/navigator", navigator, remaps)  # what the --secure router allows it
    assert "turtle2/safety/cmd_vel" in rights["publish"] and "turtle2/cmd_vel" not in rights["publish"]


def test_a_key_a_wildcard_of_the_interface_names_is_added_beside_it():
    sim = KINDS["sim"]  # subscribes to */cmd_vel: every turtle's
    i = interface_of("sim", sim.interface, {"turtle1/cmd_vel": "safe/cmd_vel_out"})
    assert i.subscribes == ("*/cmd_vel", "safe/cmd_vel_out")
    assert interface_of("sim", sim.interface) == interface_of("sim", sim.interface, {})  # none: unchanged


def test_an_undeclared_kinds_own_keys_stay_as_they_are_and_gain_the_remapped_ones():
    i = interface_of("turtle2/cruise", None, {"cruise/state": "/fleet/state"})  # its code writes cruise/state
    assert "turtle2/cruise/**" in i.publishes and "fleet/state" in i.publishes
    assert "*/cmd_vel" in i.publishes  # not turtle2/*/cmd_vel: the default's keys are not resolved again


class Relay:
    """Takes commands on turtle1/cmd_vel_in and passes them on to turtle1/cmd_vel."""

    Params = msgspec.defstruct("RelayParams", [])
    Interface = Interface(publishes=("turtle1/cmd_vel",), subscribes=("turtle1/cmd_vel_in",))

    def __init__(self, node):
        self.out = node.publisher("turtle1/cmd_vel", Twist)
        node.subscribe("turtle1/cmd_vel_in", Twist, self.out.publish)


def test_a_remapped_node_uses_the_remapped_key_and_its_interface_allows_it():
    with FakeNode(Relay, name="turtle2/relay", remaps={"turtle1/cmd_vel": "safety/cmd_vel"}) as fake:
        fake.deliver("turtle2/cmd_vel_in", Twist(linear=1.0))
        assert [m.linear for m in fake.published("turtle2/safety/cmd_vel")] == [1.0]
        assert fake.published("turtle2/cmd_vel") == []
        assert fake.node.resolve("/turtle2/cmd_vel") == "turtle2/safety/cmd_vel"  # absolute, as ROS: remapped too
        assert fake.node.interface.publishes == ("turtle2/safety/cmd_vel",)  # the key remapped away is not its own
        with pytest.raises(OutsideInterface, match="may not publish turtle2/cmd_vel_in"):
            fake.node.publisher("/turtle2/cmd_vel_in", Twist)
