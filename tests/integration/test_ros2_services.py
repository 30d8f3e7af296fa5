"""``turtlectl ros2 call`` against a real rclpy service server (the pip-installed rclpy wheels, Fast
DDS), both in one network namespace that holds only loopback: no DDS packet can leave 127.0.0.1."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.integration.harness import turtlectl
from turtlectl.runtime.client.errors import ExitCode

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[2]
ROS2_PYTHON = ROOT / ".venv-ros2" / "bin" / "python"
SERVER = Path(__file__).with_name("rclpy_services.py")
READY_WITHIN = 60.0  # s for rclpy to import and create its services on 2 busy cores
CALL_WITHIN = 60.0  # s for one turtlectl ros2 call process, its timeout included


def ros_environment() -> dict[str, str]:
    """The environment of both sides: loopback discovery, the default domain, Fast DDS for rclpy."""
    env = dict(os.environ)
    for name in ("ROS_DOMAIN_ID", "CYCLONEDDS_URI", "_ROS_WHEELS_BOOTSTRAP_COMPLETE", "LD_LIBRARY_PATH"):
        env.pop(name, None)
    env.update(ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", RMW_IMPLEMENTATION="rmw_fastrtps_cpp")
    return env


@pytest.fixture(scope="module")
def rclpy_server() -> Iterator[subprocess.Popen]:
    """The rclpy server in a fresh network namespace holding only loopback (brought up); its pid
    names the namespace the turtlectl side joins (``nsenter --net``)."""
    if not ROS2_PYTHON.exists():
        pytest.fail(f"{ROS2_PYTHON} is missing: `make ros2-side` installs the rclpy wheels there")
    if os.geteuid() != 0 or not shutil.which("unshare") or not shutil.which("nsenter"):
        pytest.fail("a loopback-only network namespace needs root, unshare and nsenter")
    inner = f"ip link set lo up && exec {ROS2_PYTHON} -u {SERVER}"
    proc = subprocess.Popen(
        ["unshare", "--net", "sh", "-c", inner],
        env=ros_environment(),
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        line = _readline(proc, READY_WITHIN)
        assert line.strip() == "READY", f"the rclpy server said {line!r}"
        yield proc
    finally:
        proc.stdin.close()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def _readline(proc: subprocess.Popen, within: float) -> str:
    """The process's next stdout line, or '' if none came within ``within`` s (a thread reads it)."""
    import threading

    lines: list[str] = []
    reader = threading.Thread(target=lambda: lines.append(proc.stdout.readline()), daemon=True)
    reader.start()
    reader.join(within)
    return lines[0] if lines else ""


def ros2_call(server: subprocess.Popen, *args: str) -> subprocess.CompletedProcess:
    """``turtlectl ros2 call ARGS`` run in the server's network namespace."""
    argv = ["nsenter", f"--net=/proc/{server.pid}/ns/net", *turtlectl(), "ros2", "call", *args]
    return subprocess.run(argv, env=ros_environment(), capture_output=True, text=True, timeout=CALL_WITHIN)


def test_set_bool_is_answered(rclpy_server):
    done = ros2_call(rclpy_server, "/set_flag", "std_srvs/srv/SetBool", "{data: true}", "--timeout", "20")
    assert done.returncode == ExitCode.OK, done.stderr
    assert done.stdout.splitlines() == [
        "# std_srvs/srv/SetBool response from /set_flag",
        "success: true",
        "message: flag True",
        "---",
    ]
    assert _readline(rclpy_server, 10).strip() == "set_flag True"


def test_a_response_that_says_no_is_exit_code_1(rclpy_server):
    done = ros2_call(rclpy_server, "/set_flag", "std_srvs/srv/SetBool", '{"data": false}', "--json", "--timeout", "20")
    assert done.returncode == ExitCode.FAILED, done.stderr
    assert done.stdout.strip() == '{"success":false,"message":"flag False"}', done.stderr
    assert done.stdout.strip() == '{"success":false,"message":"flag False"}'
    assert _readline(rclpy_server, 10).strip() == "set_flag False"


def test_trigger_and_empty_are_answered(rclpy_server):
    done = ros2_call(rclpy_server, "/trigger", "std_srvs/srv/Trigger", "--timeout", "20")
    assert done.returncode == ExitCode.OK, done.stderr
    assert "success: true" in done.stdout.splitlines() and "message: triggered" in done.stdout
    assert _readline(rclpy_server, 10).strip() == "trigger"
    done = ros2_call(rclpy_server, "reset", "std_srvs/srv/Empty", "--timeout", "20")
    assert done.returncode == ExitCode.OK, done.stderr
    assert done.stdout.splitlines()[0] == "# std_srvs/srv/Empty response from reset"
    assert _readline(rclpy_server, 10).strip() == "reset"


def test_a_missing_service_times_out_with_exit_code_3(rclpy_server):
    done = ros2_call(rclpy_server, "/no_such", "std_srvs/srv/Trigger", "--timeout", "1")
    assert done.returncode == ExitCode.UNREACHABLE
    assert done.stdout == ""
    assert done.stderr.strip() == (
        "turtlectl: error: no server of /no_such (std_srvs/srv/Trigger) within 1 s "
        "(is it served on ROS_DOMAIN_ID 0, on this host?)"
    )


def test_a_request_that_does_not_fit_is_one_line_and_exit_code_2(rclpy_server):
    done = ros2_call(rclpy_server, "/set_flag", "std_srvs/srv/SetBool", "{flag: true}")
    assert done.returncode == ExitCode.BAD_INPUT
    assert (
        done.stderr.strip() == "turtlectl: error: std_srvs/srv/SetBool has no request field 'flag' (its fields: data)"
    )
    done = ros2_call(rclpy_server, "/set_flag", "std_srvs/srv/SetBol", "{data: true}")
    assert done.returncode == ExitCode.BAD_INPUT
    assert done.stderr.startswith("turtlectl: error: unknown service type 'std_srvs/srv/SetBol' (known: ")
    assert len(done.stderr.splitlines()) == 1


if sys.platform != "linux":  # network namespaces are Linux's
    pytestmark = [pytestmark, pytest.mark.skip(reason="needs Linux network namespaces")]
