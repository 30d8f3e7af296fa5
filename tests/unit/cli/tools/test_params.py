"""cli.tools.params, the pure parts: names, dotted lookup, and TOML a launch file accepts."""

from __future__ import annotations

import tomllib
from typing import Annotated, Any

import msgspec
import pytest

from turtlectl.cli.tools.params import dump
from turtlectl.messages.keys import NodeDetails
from turtlectl.messages.world import World
from turtlectl.runtime.client.answers import names, value
from turtlectl.runtime.client.errors import BadInput, ExitCode, exit_code

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
    """`param get` says "did you mean" as `param set` does, rather than dump the whole list."""
    from turtlectl.runtime.client.answers import value
    from turtlectl.runtime.client.errors import BadInput

    with pytest.raises(
        BadInput, match=r"navigator has no parameter 'goal_timeot'; did you mean goal_timeout\? \(it has: "
    ):
        value({"goal_timeout": 30.0, "rate": 1.0}, "navigator", "goal_timeot")


def test_no_node_says_where_systems_run_when_none_runs_here(monkeypatch):
    """`--domain lab2 param get navigator ...` says more than "(running: none)"."""
    from turtlectl.runtime.client.answers import no_node
    from turtlectl.runtime.endpoint import DOMAIN_ENV

    monkeypatch.setenv(DOMAIN_ENV, "lab2")
    text = no_node(
        "navigator",
        [],
        "lab2",
        "a system runs outside any domain on this router: run the command without --domain lab2",
    ).message
    assert text == (
        "no node named 'navigator' answers in domain lab2 (no node runs in domain lab2); "
        "a system runs outside any domain on this router: run the command without --domain lab2"
    )
    assert no_node("x", ["sim"], "lab2", "ignored").message == "no node named 'x' answers in domain lab2 (running: sim)"


# -- a value refused reads the same for every node kind ---------------------------------
def _described(node: str, kind: str, params: Any):
    from turtlectl.runtime.params import describe

    return describe(node, kind, params)


def test_a_user_node_s_refusal_is_its_one_line_reason_exit_2(monkeypatch):
    """It read "turtlectl/params/mine/set rejected the request: mine: rate: Expected `float`
    <= 50.0 - at `$.rate`"."""
    from turtlectl.cli.tools import params
    from turtlectl.runtime.client import services
    from turtlectl.runtime.params import ParamRefused, with_value

    mine = _Mine()
    monkeypatch.setattr(params, "description", lambda connect, domain, node: _described(node, "mine", mine))

    def node_answers(connect, domain, key, request, timeout):  # as the node's runtime refuses
        try:
            with_value(mine, request.name, request.value)
        except ParamRefused as exc:
            raise services.Rejected(key, f"mine: {exc}") from None
        raise AssertionError("accepted")

    monkeypatch.setattr(params, "call_service", node_answers)
    with pytest.raises(BadInput) as refused:
        params.set_value("tcp/127.0.0.1:1", "", "mine", "rate", "60")
    assert refused.value.message == "mine: rate must be <= 50 (got 60)"
    assert exit_code(refused.value) == ExitCode.BAD_INPUT


def test_a_built_in_node_s_refusal_has_the_same_wording(monkeypatch):
    from turtlectl.cli.tools import params
    from turtlectl.nodes.params import NavigatorParams

    monkeypatch.setattr(
        params, "description", lambda connect, domain, node: _described(node, "navigator", NavigatorParams())
    )
    running = params.Running(
        details={"navigator": NodeDetails(name="navigator", pid=1, kind="navigator")},
        params={"navigator": msgspec.to_builtins(NavigatorParams())},
        world=World(),
    )
    monkeypatch.setattr(params, "running", lambda connect, domain: running)
    monkeypatch.setattr(params, "call_service", lambda *a: pytest.fail("sent a value the node refuses"))
    with pytest.raises(BadInput) as refused:
        params.set_value("tcp/127.0.0.1:1", "", "navigator", "goal_timeout", "-1")
    assert refused.value.message == "navigator: goal_timeout must be >= 0.1 (got -1)"


class _Mine(msgspec.Struct):
    """A user's own node kind's parameters."""

    rate: Annotated[float, msgspec.Meta(gt=0, le=50)] = 10.0


# -- a node that runs but does not answer: said as it is -------------------------------
def _graph_with_patrol():
    from turtlectl.runtime.client.graph import Graph, NodeRow

    return Graph(nodes=[NodeRow(name="patrol", pid=4242, host="vm", uptime=12.0)], topics=[], services=[])


@pytest.fixture
def silent_patrol(monkeypatch):
    """``patrol`` in the graph (its liveliness token there), its services silent: its thread
    blocked, each query running out of time."""
    from turtlectl.cli.tools import introspect, params, topics
    from turtlectl.runtime.client import services

    monkeypatch.setattr(topics, "graph", lambda connect, domain: _graph_with_patrol())

    def no_answer(connect, domain, key, request, timeout):
        raise services.NoAnswer(f"{key} did not answer within {timeout:g} s", timeout=timeout)
        yield  # a generator, as call_service is

    monkeypatch.setattr(params, "call_service", no_answer)
    monkeypatch.setattr(introspect, "call_service", no_answer)


SILENT = (
    "patrol runs (pid 4242, host vm) but did not answer {what} within 3 s: its thread is busy or blocked "
    "(a callback that has not returned?); `turtlectl log --node patrol` shows its last lines"
)


@pytest.mark.parametrize(
    ("command", "what"),
    [
        (lambda p: p.fetch("tcp/127.0.0.1:1", "", "patrol"), "with its parameters"),
        (lambda p: p.describe("tcp/127.0.0.1:1", "", "patrol", "speed"), "with its parameters' description"),
    ],
)
def test_a_running_node_that_does_not_answer_is_said_to_run_not_to_be_missing(silent_patrol, command, what):
    """`param set patrol speed 1` on a node listed as running said "no node named 'patrol'
    answers (running: patrol)"."""
    from turtlectl.cli.tools import params
    from turtlectl.runtime.client.errors import Unreachable

    with pytest.raises(Unreachable) as silent:
        command(params)
    assert silent.value.message == SILENT.format(what=what)
    assert exit_code(silent.value) == ExitCode.UNREACHABLE


def test_a_change_a_running_node_does_not_confirm_may_still_apply(silent_patrol, monkeypatch):
    from turtlectl.cli.tools import params
    from turtlectl.runtime.client.errors import Unreachable

    monkeypatch.setattr(params, "description", lambda connect, domain, node: _described(node, "mine", _Mine()))
    with pytest.raises(Unreachable) as silent:
        params.set_value("tcp/127.0.0.1:1", "", "patrol", "rate", "1")
    assert silent.value.message == (
        SILENT.format(what="to set rate").replace(
            "; `turtlectl log", "; the change may still apply once it does; `turtlectl log"
        )
    )


def test_node_info_and_log_level_of_a_silent_node_say_it_runs(silent_patrol):
    from turtlectl.cli.tools import introspect
    from turtlectl.runtime.client.errors import Unreachable

    with pytest.raises(Unreachable) as silent:
        introspect.node_report("tcp/127.0.0.1:1", "", "patrol")
    assert silent.value.message == SILENT.format(what="what it is")
    with pytest.raises(Unreachable) as silent:
        introspect.set_log_level("tcp/127.0.0.1:1", "", "patrol", "debug")
    assert silent.value.message.startswith("patrol runs (pid 4242, host vm) but did not answer to set its log level")


def test_a_node_listed_as_running_whose_service_is_gone_is_not_said_to_be_missing(monkeypatch):
    """Nothing serves its key (it is stopping, or not yet serving): it runs, named with its pid."""
    from turtlectl.cli.tools import params, topics
    from turtlectl.runtime.client import services
    from turtlectl.runtime.client.errors import Unreachable

    monkeypatch.setattr(topics, "graph", lambda connect, domain: _graph_with_patrol())

    def nobody(connect, domain, key, request, timeout):
        raise services.NobodyServes(f"nothing serves {key} (is the node running?)")
        yield

    monkeypatch.setattr(params, "call_service", nobody)
    with pytest.raises(Unreachable) as silent:
        params.fetch("tcp/127.0.0.1:1", "", "patrol")
    assert silent.value.message.startswith("patrol runs (pid 4242, host vm) but did not answer with its parameters:")
    assert "no node named" not in silent.value.message
    with pytest.raises(Unreachable, match=r"no node named 'patrl' answers; did you mean patrol\? \(running: patrol\)"):
        params.fetch("tcp/127.0.0.1:1", "", "patrl")


def test_an_unknown_node_gets_the_nearest_running_one_suggested(monkeypatch):
    from turtlectl.runtime.client.answers import no_node
    from turtlectl.runtime.endpoint import DOMAIN_ENV

    monkeypatch.delenv(DOMAIN_ENV, raising=False)
    running = ["navigator", "sim", "turtle2/navigator", "turtle2/status_monitor"]
    assert no_node("navigatr", running, "").message == (
        "no node named 'navigatr' answers; did you mean navigator? "
        "(running: navigator, sim, turtle2/navigator, turtle2/status_monitor)"
    )
    assert "did you mean turtle2/status_monitor?" in no_node("turtle2/status_monitr", running, "").message
    assert "did you mean" not in no_node("patrol", running, "").message
