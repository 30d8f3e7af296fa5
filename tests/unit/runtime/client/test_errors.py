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
