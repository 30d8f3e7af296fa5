"""cli.errors: each error by meaning has its exit code, in the one table."""

from __future__ import annotations

import pytest

from turtlectl.cli.errors import BadInput, CannotStart, ExitCode, Failed, Interrupted, Unreachable, exit_code
from turtlectl.cli.system.launchfile import LaunchFileError
from turtlectl.cli.tools.services import NoAnswer, NobodyServes, RouterLost


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
