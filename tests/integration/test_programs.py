"""A launch file runs any program (``cmd``, as ROS's ExecuteProcess) beside the
built-ins: its output prefixed with its name, told its name, domain and router in
TURTLECTL_NODE_NAME, TURTLECTL_DOMAIN and TURTLECTL_CONNECT, respawned after a kill -9,
stopped with the system; a program that is not executable is one line, exit 2, nothing started."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import textwrap
from pathlib import Path

import pytest

from tests.integration.harness import pid_alive, running_system, turtlectl

pytestmark = pytest.mark.integration

DRIVER = textwrap.dedent(
    """\
    #!/bin/sh
    echo "pid=$$ name=$TURTLECTL_NODE_NAME domain=$TURTLECTL_DOMAIN connect=$TURTLECTL_CONNECT args=$*"
    exec sleep 1000
    """
)

LAUNCH = textwrap.dedent(
    """
    [[node]]
    name = "sim"
    run = "sim"

    [[node]]
    name = "driver"
    cmd = ["./driver", "--port", "/dev/ttyUSB0"]
    respawn = true
    respawn_delay = 0.2
    """
)


@pytest.fixture
def project(tmp_path: Path) -> Path:
    driver = tmp_path / "driver"
    driver.write_text(DRIVER)
    driver.chmod(0o755)
    (tmp_path / "launch.toml").write_text(LAUNCH)
    return tmp_path


def _driver_pid(system, start: int = 0) -> int:
    i = system.wait_line(r"^driver\s*\| pid=\d+ ", 30.0, start)
    line = system.lines[i]
    assert f"name=driver domain=lab connect={system.endpoint} args=--port /dev/ttyUSB0" in line, line
    return int(re.search(r"pid=(\d+)", line)[1])


def test_a_program_runs_beside_the_builtins_supervised_as_a_node_is(project):
    with running_system(project / "launch.toml", ready=("sim",), domain="lab") as system:
        system.wait_line(r"all 2 nodes ready in", 30.0)
        first = _driver_pid(system)
        os.kill(first, signal.SIGKILL)
        after = system.wait_line(r"driver was killed by SIGKILL; respawning in 0.2 s \(respawn 1\)", 30.0)
        second = _driver_pid(system, after)
        system.wait_line(rf"started driver \(pid {second}\)", 30.0, after)
        assert second != first
        assert system.stop() == 0
        assert not pid_alive(second)
        assert "sending SIGTERM" not in system.all_output()  # stopped by the SIGINT


def test_a_program_that_is_not_executable_is_one_line_and_exit_2(project):
    (project / "driver").chmod(0o644)
    done = subprocess.run(
        [*turtlectl(), "launch", "launch.toml", "--check"], cwd=project, capture_output=True, text=True, timeout=30
    )
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        "turtlectl: error: launch.toml: node[1] (driver).cmd: ./driver is not executable"
    ]


def test_a_secure_system_refuses_programs_in_one_line(project):
    done = subprocess.run(
        [*turtlectl(), "launch", "launch.toml", "--secure", "--port", "1"],
        cwd=project,
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert done.returncode == 2, done.stdout + done.stderr
    assert "driver runs a program (cmd), which has no login" in done.stderr
