"""`turtlectl action` with arguments a user gets wrong: one line, exit code 2 (the goal service
and its types faked: no router)."""

from __future__ import annotations

import contextlib

import pytest
from typer.testing import CliRunner

from turtlectl.cli.main import app, error_line
from turtlectl.cli.tools import actions
from turtlectl.messages import NavigateToFeedback, NavigateToRequest, NavigateToResponse
from turtlectl.messages.codec import type_name
from turtlectl.runtime.client import api
from turtlectl.runtime.client.errors import ExitCode, TurtlectlError, exit_code
from turtlectl.runtime.client.graph import GoalRow, Graph

NAVIGATE = GoalRow(
    key="navigate_to",
    goal=type_name(NavigateToRequest),
    feedback=type_name(NavigateToFeedback),
    result=type_name(NavigateToResponse),
    servers=["navigator"],
)
SESSIONS: list[str] = []


@pytest.fixture(autouse=True)
def a_running_navigator(monkeypatch):
    """A system whose graph shows navigate_to; a goal that got as far as being sent fails the test."""
    SESSIONS.clear()

    @contextlib.contextmanager
    def session(connect, domain=None, role=None):
        SESSIONS.append(connect)
        yield object()

    class Book:
        def __init__(self, session):
            pass

        def learn_all(self):
            pass

    monkeypatch.setattr(api, "client_session", session)  # send-goal's Client, on no router
    graph = Graph(nodes=[], topics=[], services=[], goals=[NAVIGATE])
    monkeypatch.setattr(api, "live_graph", lambda session, domain=None: graph)
    monkeypatch.setattr(actions, "graph", lambda connect, domain: graph)
    monkeypatch.setattr(api, "TypeBook", Book)
    monkeypatch.setattr(actions.goals, "run_goal", lambda *a, **k: pytest.fail("sent a goal it should refuse"))


def invoke(*argv: str) -> tuple[int, str]:
    """Exit code and stderr's line, as main makes them from the error raised."""
    result = CliRunner().invoke(app, ["action", *argv])
    assert isinstance(result.exception, TurtlectlError), (result.exception, result.output)
    return int(exit_code(result.exception)), error_line(result.exception)


@pytest.mark.parametrize(
    "text, message",
    [
        ('{"x": 8, "y": 5', "not valid JSON: Input data was truncated"),
        ("{x: 8}", "not valid JSON: JSON is malformed: object keys must be strings (byte 1)"),
        (
            '{"x": 8, "y": 5, "theta": 90, "speed": 2}',
            "not a valid turtlectl/NavigateToRequest: Object contains unknown field `speed`",
        ),
        (
            '{"x": "far", "y": 5, "theta": 90}',
            "not a valid turtlectl/NavigateToRequest: x: Expected `float`, got `str`",
        ),
        ('{"y": 5, "theta": 90}', "not a valid turtlectl/NavigateToRequest: Object missing required field `x`"),
        ("[8, 5, 90]", "not a valid turtlectl/NavigateToRequest: Expected `object`, got `array`"),
    ],
)
def test_a_goal_that_is_not_the_goal_type_is_exit_2_in_one_line(text, message):
    code, line = invoke("send-goal", "navigate_to", text)
    assert (code, line) == (ExitCode.BAD_INPUT, f"turtlectl: error: {message}")
    assert "\n" not in line


def test_bad_json_is_said_before_any_system_is_asked():
    assert invoke("send-goal", "navigate_to", "{x")[0] == ExitCode.BAD_INPUT
    assert SESSIONS == []


@pytest.mark.parametrize("command", [["send-goal"], ["info"]])
@pytest.mark.parametrize("key", ["patrol//laps", "patrol/laps/", "patrol/$laps"])
def test_a_key_that_is_none_is_exit_2_in_one_line(command, key):
    code, line = invoke(*command, key, *(["{}"] if command == ["send-goal"] else []))
    assert code == ExitCode.BAD_INPUT and "\n" not in line, line
    assert line.startswith(f"turtlectl: error: {key!r} is not a valid key expression"), line
    assert SESSIONS == []


def test_a_goal_service_that_is_not_running_is_named_with_those_that_are():
    code, line = invoke("info", "patrol/laps")
    assert (code, line) == (
        ExitCode.UNREACHABLE,
        "turtlectl: error: no goal service patrol/laps is running (running: navigate_to)",
    )
    code, line = invoke("send-goal", "patrol/laps", '{"laps": 2}')
    assert code == ExitCode.UNREACHABLE and "`turtlectl action list` lists them" in line


def test_action_list_names_each_goal_services_types_and_server():
    from turtlectl.cli.tools.actions import rows_text
    from turtlectl.runtime.client.graph import GoalRow

    row = GoalRow("navigate_to", "turtlectl/NavigateToRequest", "turtlectl/NavigateToFeedback", "r", ["navigator"])
    assert rows_text([row]) == (
        "navigate_to  [turtlectl/NavigateToRequest -> turtlectl/NavigateToFeedback -> r]  served by navigator"
    )
