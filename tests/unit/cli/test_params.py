"""cli.params, the pure parts: names, dotted lookup, and TOML a launch file accepts."""

from __future__ import annotations

import tomllib

import pytest

from cli.errors import BadInput
from cli.params import dump, names, value

PARAMS = {
    "goal_timeout": 30.0,
    "beams": 72,
    "label": 'a "quoted" name',
    "on": True,
    "gains": {"lookahead": 0.5, "near": 0.05},
    "undeclared_obstacles": [{"x": 5.5, "y": 8.0, "radius": 0.4}],
    "empty": [],
}


def test_names_dot_into_tables_in_the_node_s_order():
    assert names(PARAMS) == [
        "goal_timeout", "beams", "label", "on", "gains.lookahead", "gains.near", "undeclared_obstacles", "empty",
    ]  # fmt: skip


def test_a_value_by_dotted_name_and_an_unknown_one_names_what_there_is():
    assert value(PARAMS, "navigator", "gains.lookahead") == 0.5
    assert value(PARAMS, "navigator", "gains") == {"lookahead": 0.5, "near": 0.05}
    with pytest.raises(
        BadInput,
        match=r"navigator has no parameter 'gains.far'; did you mean gains.near\? \(it has: goal_timeout, beams",
    ):
        value(PARAMS, "navigator", "gains.far")
    with pytest.raises(BadInput, match="no parameter 'beams.x'"):
        value(PARAMS, "navigator", "beams.x")


def test_dump_is_toml_that_reads_back_as_the_same_table():
    text = dump("navigator", PARAMS)
    assert text.startswith("# navigator: the body of its [node.params] table")
    assert tomllib.loads(text) == PARAMS


def test_an_unknown_parameter_suggests_the_nearest():
    """Review of issue 13: `param get` dumped the whole list where `param set` said "did you mean"."""
    from cli.errors import BadInput
    from cli.params import value

    with pytest.raises(
        BadInput, match=r"navigator has no parameter 'goal_timeot'; did you mean goal_timeout\? \(it has: "
    ):
        value({"goal_timeout": 30.0, "rate": 1.0}, "navigator", "goal_timeot")


def test_no_node_says_where_systems_run_when_none_runs_here(monkeypatch):
    """Second review of issue 13: `--domain lab2 param get navigator ...` said "(running: none)" and no more."""
    from cli.params import no_node
    from runtime.endpoint import DOMAIN_ENV

    monkeypatch.setenv(DOMAIN_ENV, "lab2")
    text = no_node(
        "navigator", [], "a system runs outside any domain on this router: run the command without --domain lab2"
    ).message
    assert text == (
        "no node named 'navigator' answers in domain lab2 (no node runs in domain lab2); "
        "a system runs outside any domain on this router: run the command without --domain lab2"
    )
    assert no_node("x", ["sim"], "ignored").message == "no node named 'x' answers in domain lab2 (running: sim)"
