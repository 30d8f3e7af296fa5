"""Node selectors (cli.selection): the one rule of launch --only/--exclude, log --node,
log-level and param: names, globs, namespaces and turtles."""

from __future__ import annotations

from turtlectl.cli.selection import is_glob, selected, selects, unmatched

DEFAULT = ["sim", "navigator", "status_monitor", "obstacle_detector"]
FLEET = [*DEFAULT, "turtle2/navigator", "turtle2/status_monitor", "turtle3/navigator", "turtle22/navigator"]
SYMMETRIC = ["sim", "turtle1/navigator", "turtle1/status_monitor", "turtle2/navigator"]


def test_a_name_names_its_node_only():
    assert selected(["navigator"], FLEET) == ["navigator"]
    assert selected(["/turtle2/navigator"], FLEET) == ["turtle2/navigator"]  # ROS's leading slash
    assert not selects("Navigator", "navigator")  # names are case-sensitive, as keys are


def test_globs_match_full_names():
    assert selected(["turtle2/*"], FLEET) == ["turtle2/navigator", "turtle2/status_monitor"]
    assert selected(["*/navigator"], FLEET) == ["turtle2/navigator", "turtle3/navigator", "turtle22/navigator"]
    assert selected(["status*"], FLEET) == ["status_monitor"]
    assert is_glob("turtle2/*") and not is_glob("turtle2")


def test_a_namespace_names_its_nodes():
    assert selected(["turtle2"], FLEET) == ["turtle2/navigator", "turtle2/status_monitor"]
    assert selected(["turtle1"], SYMMETRIC) == ["turtle1/navigator", "turtle1/status_monitor"]


def test_a_turtle_names_the_nodes_that_drive_it_never_the_simulator():
    # turtle1's nodes outside any namespace (the default launch file): every one but the simulator
    assert selected(["turtle1"], FLEET) == ["navigator", "status_monitor", "obstacle_detector"]
    assert selected(["turtle1"], ["sim", "navigator"], {"sim": "sim", "navigator": "navigator"}) == ["navigator"]
    # a simulator of another name is known by its kind
    assert selected(["turtle1"], ["world", "navigator"], {"world": "sim", "navigator": "navigator"}) == ["navigator"]
    assert selected(["sim"], FLEET) == ["sim"]


def test_unmatched_selectors_are_named():
    assert unmatched(["turtle2", "turtle9", "nav*x"], FLEET) == ["turtle9", "nav*x"]
    assert unmatched(["turtle1"], DEFAULT) == []
