"""``turtlectl ros2 call``'s checks before any DDS: one line and its exit code for each bad input."""

from __future__ import annotations

import sys

import pytest

from turtlectl.cli.tools import ros2_call
from turtlectl.runtime.client.errors import BadInput, CannotStart, ExitCode


def test_without_cyclone_dds_the_line_says_how_to_install_the_extra(monkeypatch):
    for name in [m for m in sys.modules if m == "cyclonedds" or m.startswith(("cyclonedds.", "turtlectl.nodes.ros2_"))]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "cyclonedds", None)  # import cyclonedds raises ImportError
    with pytest.raises(CannotStart) as caught:
        ros2_call.call("/set_flag", "std_srvs/srv/SetBool", "{data: true}", 1.0)
    assert caught.value.message == (
        "ROS 2 needs Cyclone DDS's Python binding, which is not installed (pip install 'turtlectl[ros2]')"
    )
    assert caught.value.exit_code == ExitCode.CANNOT_START


@pytest.mark.parametrize(
    ("service", "ros_type", "request_text", "message"),
    [
        (
            "/a b",
            "std_srvs/srv/Empty",
            "",
            "'/a b' is no ROS service name (as /set_flag or /turtle1/teleport_absolute)",
        ),
        (
            "/x",
            "std_srvs/srv/SetBool",
            "{data: maybe}",
            "std_srvs/srv/SetBool field 'data' (bool) takes true or false, not 'maybe'",
        ),
        (
            "/x",
            "std_srvs/srv/SetBool",
            "{data",
            "cannot read the request '{data': give 'field: value' pairs, as '{data: true}'",
        ),
    ],
)
def test_bad_input_is_one_line_before_anything_is_sent(service, ros_type, request_text, message):
    with pytest.raises(BadInput) as caught:
        ros2_call.call(service, ros_type, request_text, 1.0)
    assert caught.value.message == message


def test_a_bad_ros_domain_id_is_bad_input(monkeypatch):
    monkeypatch.setenv("ROS_DOMAIN_ID", "x")
    with pytest.raises(BadInput, match="ROS_DOMAIN_ID='x': give a whole number from 0 to 232"):
        ros2_call.call("/x", "std_srvs/srv/Empty", "", 1.0)


def test_the_response_is_a_block_as_call_prints():
    text = ros2_call.response_text("/set_flag", "std_srvs/srv/SetBool", {"success": True, "message": "ok"})
    assert text.splitlines() == [
        "# std_srvs/srv/SetBool response from /set_flag",
        "success: true",
        "message: ok",
        "---",
    ]
