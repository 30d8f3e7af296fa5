"""cli: which command a command line runs, and which commands a Ctrl-C stops normally."""

from __future__ import annotations

import pytest

from turtlectl.cli import STOPPED_BY_CTRL_C, command_of


@pytest.mark.parametrize(
    "argv, command",
    [
        (["launch", "--port", "7448"], "launch"),
        (["--domain", "lab1", "launch"], "launch"),
        (["--domain=lab1", "router"], "router"),
        (["--connect", "tcp/127.0.0.1:7448", "launch"], "launch"),  # not "tcp/…" (then exit 130)
        (["--connect=tcp/127.0.0.1:7448", "--domain", "x", "router"], "router"),
        (["goto", "1", "2", "3"], "goto"),
        (["--version"], ""),
        ([], ""),
    ],
)
def test_the_command_of_a_command_line(argv, command):
    assert command_of(argv) == command


def test_ctrl_c_is_a_normal_stop_only_for_the_long_running_servers():
    assert STOPPED_BY_CTRL_C == ("launch", "router")
