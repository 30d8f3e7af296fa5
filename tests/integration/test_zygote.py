"""The zygote in a real launch: nodes are forked by it (not started by exec), and when it dies
its nodes die with it and come back as new processes, supervision going on (said once)."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import pytest

from tests.integration.harness import pid_alive, running_system

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


def test_nodes_are_forked_by_the_zygote_and_outlive_its_death_as_new_processes(tmp_path):
    path = tmp_path / "both.toml"
    path.write_text(BOTH_RESPAWN)
    with running_system(path, ready=("sim", "status_monitor")) as system:
        zygote = _zygote_of(system.proc.pid)
        first = dict(system.alive)
        assert all(_parent_of(pid) == zygote for pid in first.values())
        os.kill(zygote, signal.SIGKILL)
        system.wait_until(lambda: all(system.alive.get(n, p) != p for n, p in first.items()), 20.0, "both nodes back")
        assert not [p for p in first.values() if pid_alive(p)]  # they died with the zygote
        assert all(_parent_of(pid) == system.proc.pid for pid in system.alive.values())  # started by exec now
        out = system.output()
        assert out.count("starting nodes as new processes") == 1, out
        assert "sim was killed by SIGTERM; respawning" in out
        assert "Traceback" not in out
