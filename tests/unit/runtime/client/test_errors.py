"""runtime.client.errors: each error by meaning has its exit code, in the one table."""

from __future__ import annotations

import pytest

from turtlectl.cli.system.launchfile import LaunchFileError
from turtlectl.messages import NavigateToResponse
from turtlectl.runtime.client.errors import (
    BadInput,
    CannotStart,
    ExitCode,
    Failed,
    Interrupted,
    Unreachable,
    exit_code,
    goal_exit_code,
)
from turtlectl.runtime.client.services import NoAnswer, NobodyServes, RouterLost, reply_code


@pytest.mark.parametrize(
    "error, code",
    [
        (BadInput("x"), ExitCode.BAD_INPUT),
        (Unreachable("x"), ExitCode.UNREACHABLE),
        (CannotStart("x"), ExitCode.CANNOT_START),
        (Failed("x"), ExitCode.FAILED),
        (Interrupted("x"), ExitCode.INTERRUPTED),
        (LaunchFileError("x"), ExitCode.BAD_INPUT),
        (NoAnswer("x", answered=True), ExitCode.FAILED),
        (NobodyServes("x"), ExitCode.UNREACHABLE),
        (RouterLost("x"), ExitCode.UNREACHABLE),
    ],
)
def test_each_error_has_the_exit_code_of_its_meaning(error, code):
    assert exit_code(error) == code and error.message == "x"


def test_a_launch_file_error_is_still_a_value_error_whose_text_is_the_message():
    error = LaunchFileError("launch.toml: node[0]: oops")
    assert isinstance(error, ValueError) and str(error) == error.message == "launch.toml: node[0]: oops"


@pytest.mark.parametrize(
    "reason, code",
    [
        ("invalid goal", ExitCode.BAD_INPUT),  # inside an obstacle: as a teleport there
        ("unreachable", ExitCode.FAILED),
        ("battery low", ExitCode.FAILED),
        ("blocked", ExitCode.FAILED),
        ("timeout", ExitCode.FAILED),
    ],
)
def test_a_goal_refused_for_itself_exits_as_a_teleport_refused_there_and_any_other_end_1(reason, code):
    response = NavigateToResponse(success=False, time_taken=0.0, reason=reason, refused=reason != "blocked")
    assert goal_exit_code(response) == code and reply_code(response) == code
    assert goal_exit_code(NavigateToResponse(success=True, time_taken=1.0)) == ExitCode.OK


def test_the_runtimes_errors_are_turtlectl_errors_with_the_exit_code_of_their_meaning():
    import turtlectl
    from turtlectl.nodes.kinds import KindError
    from turtlectl.runtime.futures import FutureError
    from turtlectl.runtime.goal_client import GoalFailed
    from turtlectl.runtime.interface import OutsideInterface
    from turtlectl.runtime.loader import LoadError
    from turtlectl.runtime.node import NodeConflict
    from turtlectl.runtime.params import ParamRefused

    cases = [
        (GoalFailed("patrol/laps", "gone", node="patrol", pid=42), ExitCode.FAILED),
        (FutureError("no result within 1 s"), ExitCode.FAILED),
        (NodeConflict("navigator", 42, "serves navigate_to"), ExitCode.CANNOT_START),
        (OutsideInterface("mine", "publish", "a/b", ()), ExitCode.BAD_INPUT),
        (LoadError("x"), ExitCode.BAD_INPUT),
        (ParamRefused("x"), ExitCode.BAD_INPUT),
        (KindError("x"), ExitCode.BAD_INPUT),
    ]
    for error, code in cases:
        assert isinstance(error, turtlectl.Error) and error.exit_code == code, error
    gone = cases[0][0]
    assert str(gone) == "patrol/laps's server patrol (pid 42) went away before the goal ended"
    assert (gone.key, gone.why, gone.node, gone.pid) == ("patrol/laps", "gone", "patrol", 42)
    assert isinstance(LoadError("x"), ValueError)  # still caught where a ValueError is


def test_an_error_located_is_made_again_from_its_fields_not_by_editing_its_text():
    nobody = NobodyServes("nothing serves navigate_to", "is the node running?")
    assert nobody.message == "nothing serves navigate_to (is the node running?)"
    hint = "; systems run in domain lab2 on this router: add it before the command"
    located = nobody.located("lab1", hint)
    assert located.message == f"nothing serves navigate_to in domain lab1 (is the node running?){hint}"
    assert (located.what, located.domain, located.said) == (
        "nothing serves navigate_to",
        "lab1",
        "nothing serves navigate_to in domain lab1",
    )
    lost = RouterLost(during="before the goal ended").located("tcp/127.0.0.1:7447")
    assert lost.message == "lost the router at tcp/127.0.0.1:7447 before the goal ended (did `turtlectl launch` stop?)"
    assert lost.connect == "tcp/127.0.0.1:7447" and lost.said.endswith("before the goal ended")
