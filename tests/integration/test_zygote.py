"""The zygote in a real launch: nodes are forked by it (not started by exec) and handed to the
supervisor as its children; when it dies its nodes go on, and later starts are new processes,
supervision going on (said once)."""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import pytest

from tests.integration.harness import System, pid_alive, running_system, session_members
from turtlectl.messages import TurtleStatus
from turtlectl.messages.keys import STATUS

pytestmark = pytest.mark.integration

BOTH_RESPAWN = """
[[node]]
name = "sim"
run = "sim"
respawn = true
respawn_delay = 0.1
[[node]]
name = "status_monitor"
run = "status_monitor"
respawn = true
respawn_delay = 0.1
"""


def _zygote_of(supervisor: int) -> int:
    """The supervisor's child named turtle-zygote."""
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        comm = stat[stat.index("(") + 1 : stat.rindex(")")]
        ppid = int(stat.rsplit(") ", 1)[1].split()[1])
        if comm == "turtle-zygote" and ppid == supervisor:
            return int(entry.name)
    raise AssertionError(f"no zygote under the supervisor (pid {supervisor})")


def _parent_of(pid: int) -> int:
    return int(Path(f"/proc/{pid}/stat").read_text().rsplit(") ", 1)[1].split()[1])


def test_nodes_are_forked_by_the_zygote_and_outlive_its_death(tmp_path):
    """Killing the zygote kills no node it has forked."""
    path = tmp_path / "both.toml"
    path.write_text(BOTH_RESPAWN)
    with running_system(path, ready=("sim", "status_monitor")) as system:
        zygote = _zygote_of(system.proc.pid)
        first = dict(system.alive)
        assert all(_parent_of(pid) == system.proc.pid for pid in first.values())  # handed over
        assert all(Path(f"/proc/{pid}/comm").read_text().strip() == name for name, pid in first.items())  # forked
        os.kill(zygote, signal.SIGKILL)
        system.wait_until(lambda: not pid_alive(zygote), 5.0, "the zygote's end")
        system.collect(STATUS, TurtleStatus, 3, timeout=5.0)  # the system goes on as it was
        assert dict(system.alive) == first and all(pid_alive(p) for p in first.values())
        os.kill(first["sim"], signal.SIGKILL)  # a node's end is still seen, with its real cause
        system.wait_until(lambda: system.alive.get("sim", first["sim"]) != first["sim"], 20.0, "sim back")
        assert _parent_of(system.alive["sim"]) == system.proc.pid
        out = system.output()
        said = f"the zygote (pid {zygote}) was killed by SIGKILL; running nodes go on, the next ones start as new processes"
        assert out.count(said) == 1 and "starting nodes as new processes" not in out, out  # said once, when it died
        assert "sim was killed by SIGKILL; respawning" in out
        assert "Traceback" not in out


@pytest.mark.parametrize("when", ["first node started", "all nodes started"])
def test_a_supervisor_killed_while_its_nodes_start_leaves_nothing_within_a_second(when):
    """Nodes still starting do not linger 1-2 s (a claim asking a router that died with the
    supervisor; a fork waiting for its parent)."""
    pattern = r"started sim \(pid" if when == "first node started" else r"started obstacle_detector \(pid"
    system = System()
    try:
        system.wait_line(pattern, 20.0)
        os.kill(system.proc.pid, signal.SIGKILL)
        killed = time.monotonic()
        system.proc.wait(5)
        deadline = killed + 5.0
        while session_members(system.proc.pid) and time.monotonic() < deadline:
            time.sleep(0.01)  # pacing: polling /proc under a deadline
        gone_after = time.monotonic() - killed
        assert not session_members(system.proc.pid), "processes outlived their supervisor"
        assert gone_after < 1.0, f"the last one ended {gone_after:.2f} s after the supervisor"
    finally:
        system.kill_everything()
