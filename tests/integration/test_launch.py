"""The launch supervisor: phantom detections, shutdown, required and respawned nodes, `make run`, old run folders (the capstone's launch criteria are in test_criteria.py)."""

from __future__ import annotations

import math
import os
import re
import signal
import subprocess
import time

import pytest

from tests.integration.harness import ROOT, System, pid_alive, running_system
from turtlectl.messages import LaserScan, TurtleStatus
from turtlectl.messages.keys import OBSTACLES, STATUS

pytestmark = pytest.mark.integration


PHANTOMS = """
[[node]]
name = "sim"
run = "sim"
[[node]]
name = "obstacle_detector"
run = "obstacle_detector"
[node.params]
range_max = 3.0
phantom_rate = 20.0
phantom_lifetime = 0.4
phantom_distance = 1.5
phantom_radius = 0.2
"""


def test_phantom_detections_come_and_go(tmp_path):
    path = tmp_path / "phantoms.toml"
    path.write_text(PHANTOMS)
    with running_system(path, ready=("sim", "obstacle_detector")) as system:
        scans = [s for _, s in system.collect(OBSTACLES, LaserScan, 10, timeout=10.0)]
    nearest = [min(s.ranges) for s in scans]  # walls are 5.5 m away: beyond range_max
    assert any(abs(r - 1.3) < 0.05 for r in nearest), nearest
    assert all(r == math.inf or r >= 1.3 - 0.05 for r in nearest)


def test_respawned_node_comes_back_with_a_new_pid(custom):
    old = custom.alive["status_monitor"]
    os.kill(old, signal.SIGKILL)
    custom.wait_until(lambda: custom.alive.get("status_monitor", old) != old, 10.0, "a new status_monitor")
    custom.collect(STATUS, TurtleStatus, 2, timeout=5.0)
    custom.wait_line(r"status_monitor was killed by SIGKILL; respawning", 2.0)


def test_required_node_death_stops_the_whole_system():
    with running_system() as system:
        pids = system.wait_ready()
        os.kill(pids["sim"], signal.SIGKILL)
        assert system.proc.wait(10.0) == 1
        assert "required node sim was killed by SIGKILL" in system.output()
        assert not [p for p in pids.values() if pid_alive(p)]


def test_sigint_stops_every_child_within_five_seconds():
    with running_system() as system:
        pids = system.wait_ready()
        started = time.monotonic()
        assert system.stop(signal.SIGINT) == 0
        assert time.monotonic() - started < 5.0
        assert not [p for p in pids.values() if pid_alive(p)]
        assert "stopped (received SIGINT); exit code 0" in system.output()


def test_children_do_not_outlive_a_killed_supervisor():
    with running_system() as system:
        pids = system.wait_ready()
        os.killpg(system.proc.pid, signal.SIGKILL)  # the supervisor's group only: children have their own
        system.proc.wait(5.0)
        deadline = time.monotonic() + 5.0
        while any(pid_alive(p) for p in pids.values()) and time.monotonic() < deadline:
            time.sleep(0.05)  # pacing: polling process state under a deadline
        assert not [p for p in pids.values() if pid_alive(p)]


def test_make_run_takes_args_and_a_busy_port_names_the_way_out(custom, tmp_path):
    make = subprocess.Popen(
        ["make", "--no-print-directory", "run", f"ARGS=--port {custom.port} --log-dir {tmp_path}"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        stdin=subprocess.DEVNULL,
        start_new_session=True,
    )
    try:
        stdout, stderr = make.communicate(timeout=60)
    finally:
        if make.poll() is None:  # a launch that did start (ARGS ignored): stop it, as Ctrl-C would
            os.killpg(make.pid, signal.SIGINT)
            try:
                make.communicate(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(make.pid, signal.SIGKILL)
                make.communicate()
    result = subprocess.CompletedProcess(make.args, make.returncode, stdout, stderr)
    assert f"launch --port {custom.port} --log-dir" in result.stdout  # make ran it with ARGS
    assert "the port is already in use" in result.stderr, result.stderr
    # what was typed, with the next free port above (port + 1 unless another test holds it at that moment)
    suggested = re.search(r"choose another: make run ARGS='--port (\d+) --log-dir (\S+)'", result.stderr)
    assert suggested is not None and int(suggested[1]) > custom.port, result.stderr
    assert suggested[2] == str(tmp_path), result.stderr
    assert "Error 4" in result.stderr and "Traceback" not in result.stderr
    assert list(tmp_path.iterdir()) == []  # a launch that could not start leaves no log folder


KEEP_TWO = """
[supervisor]
keep_logs = 2
[[node]]
name = "sim"
run = "sim"
"""


def test_old_run_folders_are_pruned_at_launch(tmp_path):
    logs = tmp_path / "logs"
    old = [logs / f"2020-01-0{day}-12-00-00-{4194300 + day}" for day in range(1, 5)]  # pids that run nothing
    for folder in old:
        folder.mkdir(parents=True)
        (folder / "sim.log").write_text("old\n")
    (logs / "mine").mkdir()
    path = tmp_path / "keep_two.toml"
    path.write_text(KEEP_TWO)
    with running_system(path, ready=("sim",), extra_args=("--log-dir", str(logs))) as system:
        current = system.lines[system.wait_line(r"logs in ", 5.0)].split("logs in ")[1]
        assert sorted(p.name for p in logs.iterdir()) == sorted([old[-1].name, os.path.basename(current), "mine"])


NOISE = ("Traceback", "Fatal Python error", "KeyboardInterrupt")


def _stopped_quietly(system: System, code: int) -> str:
    """A stop on request: exit 0 (or the process died of the SIGINT before Python ran a line,
    saying nothing), no traceback from anyone, and no child left."""
    out = system.all_output()
    assert code == 0 or (code == -signal.SIGINT and not out), (code, out)
    assert not [word for word in NOISE if word in out], out
    assert not [p for p in system.child_pids if pid_alive(p)], out
    return out


@pytest.mark.parametrize("delay", [0.0, 0.2, 0.5])
def test_ctrl_c_while_the_nodes_start_is_quiet(delay):
    """Ctrl-C about a second after `make run`: every node is still importing (numpy, zenoh)."""
    system = System()
    try:
        system.wait_line(r"started obstacle_detector", 30.0)  # the last one: all four are starting now
        time.sleep(delay)  # pacing: into the nodes' imports (about a second), which announce nothing
        out = _stopped_quietly(system, system.stop(signal.SIGINT))
        assert len(system.child_pids) == 4 and "stopped (received SIGINT); exit code 0" in out, out
    finally:
        system.kill_everything()


@pytest.mark.parametrize("delay", [0.1, 0.4, 0.8])
def test_ctrl_c_while_the_supervisor_starts_is_quiet(delay):
    """Ctrl-C while `turtlectl launch` itself imports typer and zenoh, or reads the launch file."""
    system = System()
    try:
        time.sleep(delay)  # pacing: a point in the supervisor's own start-up, which announces nothing to wait on
        _stopped_quietly(system, system.stop(signal.SIGINT))
    finally:
        system.kill_everything()
