"""Supervision that survives faults, against the real processes: respawn with backoff,
required nodes, logs, partial systems, a router restart, domains, kill -9 mid-goal, garbage."""

from __future__ import annotations

import json
import math
import os
import re
import signal
import subprocess
import textwrap
import time
from pathlib import Path

import msgspec
import pytest

from tests.integration.harness import NODES, Router, pid_alive, running_system, turtlectl
from turtlectl.messages import TurtleStatus
from turtlectl.messages.keys import STATUS

pytestmark = pytest.mark.integration

FLAKY_MONITOR = """
[[node]]
name = "sim"
run = "sim"
[[node]]
name = "status_monitor"
run = "status_monitor"
required = true
respawn = true
respawn_delay = 0.2
respawn_max = 2
"""


def test_respawn_backs_off_then_a_required_node_that_keeps_dying_stops_the_system(tmp_path):
    path = tmp_path / "flaky.toml"
    path.write_text(FLAKY_MONITOR)
    with running_system(path, ready=("sim", "status_monitor")) as system:
        for _ in range(2):
            pid = system.alive["status_monitor"]
            os.kill(pid, signal.SIGKILL)
            system.wait_until(lambda p=pid: system.alive.get("status_monitor", p) != p, 10.0, "respawned monitor")
        os.kill(system.alive["status_monitor"], signal.SIGKILL)
        assert system.proc.wait(10) == 1
        out = system.output()
        assert "respawning in 0.2 s (respawn 1)" in out and "respawning in 0.4 s (respawn 2)" in out
        assert "status_monitor was killed by SIGKILL, after 2 respawns in a row; giving up on it; it is required" in out
        assert "stopped (required node status_monitor" in out


def test_each_node_logs_to_its_own_file_in_the_run_folder(system):
    folder = re.search(r"logs in (\S+)", system.output())
    assert folder, system.output()
    files = {p.name for p in Path(folder.group(1)).iterdir()}
    assert files == {f"{n}.log" for n in NODES} | {"launch.log"}
    sim_log = (Path(folder.group(1)) / "sim.log").read_text()
    assert f"ready (pid {system.alive['sim']})" in sim_log
    assert "|" not in sim_log.splitlines()[0]  # no prefix, no colour in the files


def test_check_only_exclude_and_set():
    check = subprocess.run(
        [*turtlectl(), "launch", "--check", "--exclude", "obstacle_detector", "--set", "navigator.goal_timeout=42"],
        capture_output=True,
        text=True,
        timeout=20,
    )
    assert check.returncode == 0, check.stderr
    assert "  sim (run sim; required)" in check.stdout and "obstacle_detector" not in check.stdout
    assert (
        "navigator (run navigator; optional; respawn after 1 s" in check.stdout
        and '"goal_timeout":42.0' in check.stdout
    )
    bad = subprocess.run(
        [*turtlectl(), "launch", "--check", "--set", "navigator.speed=3"], capture_output=True, text=True, timeout=20
    )
    assert bad.returncode == 2 and "--set navigator.speed: unknown key" in bad.stderr
    with running_system(
        ready=("sim", "navigator"),
        extra_args=("--only", "sim", "--only", "navigator", "--set", "navigator.goal_timeout=42"),
    ) as system:
        graph = json.loads(system.run_cli("list", "--json").stdout)
        assert {n["name"] for n in graph["nodes"]} == {"sim", "navigator"}
        params = json.loads(system.run_cli("call", "turtlectl/params/navigator").stdout)
        assert params["goal_timeout"] == 42.0


@pytest.fixture()
def router():
    r = Router()
    r.start()
    yield r
    r.kill()


def test_nodes_come_back_by_themselves_after_the_router_restarts(router):
    with running_system(join=router.endpoint) as system:
        pids = dict(system.alive)
        router.kill()
        system.wait_line(r"navigator .*lost the router", 10.0)
        router.start()
        system.wait_line(r"navigator .*router at .* is reached", 15.0)
        # a fresh client sees the same processes and the system works
        deadline = time.monotonic() + 15
        while True:
            result = system.run_cli("list", "--json")
            nodes = {n["name"]: n["pid"] for n in json.loads(result.stdout)["nodes"]} if result.returncode == 0 else {}
            if nodes == pids:
                break
            assert time.monotonic() < deadline, f"graph after the restart: {nodes}"
        goal = system.run_cli("goto", "3", "3", "0")
        assert goal.returncode == 0, goal.stdout + goal.stderr


def test_two_domains_on_one_router_never_mix(router):
    with (
        running_system(join=router.endpoint, domain="alpha") as a,
        running_system(join=router.endpoint, domain="beta") as b,
    ):
        graph_a = json.loads(a.run_cli("list", "--json").stdout)
        assert {n["pid"] for n in graph_a["nodes"]} == set(a.alive.values())
        assert not set(a.alive.values()) & set(b.alive.values())
        before_b = b.latest_pose()
        assert a.run_cli("goto", "3", "7.5", "90").returncode == 0
        after_a, after_b = a.latest_pose(), b.latest_pose()
        assert math.hypot(after_a.x - 3, after_a.y - 7.5) < 0.01
        assert (after_b.x, after_b.y) == (before_b.x, before_b.y)
        plain = subprocess.run(
            [*turtlectl(), "echo", "robot/status", "--timeout", "3.5", "--connect", router.endpoint],
            capture_output=True,
            text=True,
            timeout=20,
        )
        assert plain.returncode == 3  # outside any domain there is nothing


def test_kill_9_the_navigator_mid_goal(system):
    system.teleport(1.0, 5.5, 0.0)
    goto = subprocess.Popen(
        [*turtlectl(), "goto", "10", "5.5", "0", "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    system.wait_moving(1.0)
    old = system.alive["navigator"]
    os.kill(old, signal.SIGKILL)
    killed = time.monotonic()
    out, err = goto.communicate(timeout=10)
    assert goto.returncode == 1 and "navigator stopped answering" in err, (out, err)
    stopped = system.wait_stopped(5.0)  # the sim's 1 s cmd_vel timeout, then braking
    assert stopped.x < 10.0 - 0.5
    system.wait_until(lambda: system.alive.get("navigator", old) != old, 10.0, "navigator respawned")
    recovered = time.monotonic() - killed
    goal = system.run_cli("goto", "3", "5.5", "0")
    assert goal.returncode == 0, goal.stdout + goal.stderr
    print(f"navigator back {recovered:.2f} s after kill -9")


@pytest.mark.parametrize("victim", ["status_monitor", "obstacle_detector"])
def test_kill_9_a_helper_mid_goal_does_not_fail_the_goal(system, victim):
    system.teleport(2.0, 2.0, 0.0)
    old = system.alive[victim]
    goto = subprocess.Popen(
        [*turtlectl(), "goto", "7", "4", "90", "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    system.wait_moving(0.5)
    os.kill(old, signal.SIGKILL)
    out, err = goto.communicate(timeout=20)
    assert goto.returncode == 0, out + err
    system.wait_until(lambda: system.alive.get(victim, old) != old, 10.0, f"{victim} respawned")


GARBAGE = [
    b"",
    b"\xc1",
    b"not msgpack",
    msgspec.msgpack.encode({"type": "turtlectl/Twist", "linear": "x"}),
    b"\x00" * 4096,
]


def test_garbage_on_every_key_is_dropped_and_logged_once_per_key(system):
    pids = dict(system.wait_ready())
    start = len(system.lines)
    topics = ["turtle1/cmd_vel", "turtle1/pose", "robot/status", "obstacles", "navigate_to/feedback"]
    services = ["navigate_to", "navigate_to/cancel", "turtle1/teleport_absolute", "reset"]
    for _ in range(3):
        for key in topics:
            for payload in GARBAGE:
                system.session.put(key, payload)
        for key in services:
            for payload in GARBAGE:
                replies = list(system.session.get(key, payload=payload, timeout=5.0))
                assert replies and all(r.err is not None for r in replies), key
    goal = system.run_cli("goto", "5", "5", "0")
    assert goal.returncode == 0, goal.stdout + goal.stderr
    system.collect(STATUS, TurtleStatus, 2, timeout=5.0)
    assert system.alive == pids
    for node, key in [
        ("sim", "turtle1/cmd_vel"),
        ("navigator", "turtle1/pose"),  # read when a goal starts (a ring channel), garbage counted then
        ("navigator", "navigate_to"),
        ("status_monitor", "turtle1/pose"),
        ("sim", "reset"),
        ("status_monitor", "reset"),
    ]:
        system.wait_line(rf"{node} .*dropped malformed payload #1 on {re.escape(key)}:", 5.0, start)
    logged = [line for line in system.lines[start:] if "dropped malformed payload" in line]
    # 15 payloads per topic key (3 rounds x 5): logged once per key and node, not once per message
    assert len(logged) <= len({(line.split("|")[0].strip(), line.split(" on ")[1].split(":")[0]) for line in logged})
    assert not any("Traceback" in line for line in system.lines)


STUBBORN = """
[supervisor]
sigint_timeout = 0.5
sigterm_timeout = 0.5

[[node]]
name = "sim"
run = "sim"
[[node]]
name = "navigator"
run = "navigator"
"""


def test_shutdown_escalates_to_sigkill_for_a_child_that_does_not_stop(tmp_path):
    path = tmp_path / "stubborn.toml"
    path.write_text(STUBBORN)
    with running_system(path, ready=("sim", "navigator")) as system:
        pids = dict(system.alive)
        os.kill(pids["navigator"], signal.SIGSTOP)  # a stopped process handles neither SIGINT nor SIGTERM
        started = time.monotonic()
        assert system.stop(signal.SIGINT) == 0
        took = time.monotonic() - started
        out = system.output()
        assert "sending SIGTERM to navigator" in out and "sending SIGKILL to navigator" in out
        assert "sending SIGTERM to sim" not in out  # sim stopped on its SIGINT
        assert 1.0 <= took < 3.0, took  # the two 0.5 s waits, then the kill
        assert not [p for p in pids.values() if pid_alive(p)]


def test_a_goal_fails_cleanly_when_poses_stop(system):
    system.teleport(2.0, 5.0, 0.0)
    goto = subprocess.Popen(
        [*turtlectl(), "goto", "9", "5", "0", "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    sim = system.alive["sim"]
    try:
        system.wait_moving(0.5)
        os.kill(sim, signal.SIGSTOP)  # the simulator freezes: no more poses
        out, err = goto.communicate(timeout=10)
        assert goto.returncode == 1 and "not reached: no pose after" in out, out + err
    finally:
        os.kill(sim, signal.SIGCONT)
    system.latest_pose()  # poses flow again


def test_kill_9_the_required_sim_mid_goal_stops_everything_and_tells_the_caller():
    with running_system() as system:
        pids = dict(system.alive)
        goto = subprocess.Popen(
            [*turtlectl(), "goto", "9", "4", "0", "--connect", system.endpoint],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        system.wait_moving(0.5)
        os.kill(pids["sim"], signal.SIGKILL)
        out, err = goto.communicate(timeout=10)
        assert goto.returncode == 1, out + err
        assert "no pose" in out or "navigator shut down" in out or "stopped answering" in err, out + err
        assert system.proc.wait(10) == 1
        assert not [p for p in pids.values() if pid_alive(p)]


@pytest.mark.parametrize("goal", [(10.0, 6.0, 0.0), (10.5, 7.0, 0.0), (7.0, 10.0, 0.0)])
def test_turning_away_from_an_obstacle_is_never_blocked(system, goal):
    system.teleport(8.3, 8.3, math.radians(45))  # facing the obstacle at (9, 9), r 0.6, 0.39 m away
    result = system.run_cli("goto", *(f"{v:g}" for v in goal))
    assert result.returncode == 0, result.stdout + result.stderr


NO_RESPAWN = """
[[node]]
name = "sim"
run = "sim"
[[node]]
name = "status_monitor"
run = "status_monitor"
[[node]]
name = "obstacle_detector"
run = "obstacle_detector"
"""


def test_a_node_that_is_gone_for_good_is_reported_once(tmp_path):
    path = tmp_path / "no_respawn.toml"
    path.write_text(NO_RESPAWN)
    with running_system(path, ready=("sim", "status_monitor", "obstacle_detector")) as system:
        os.kill(system.alive["obstacle_detector"], signal.SIGKILL)
        system.wait_line(r"obstacle_detector was killed by SIGKILL", 5.0)
        system.collect(STATUS, TurtleStatus, 15, timeout=5.0)  # 1.5 s of the system going on
        reports = [line for line in system.lines if "obstacle_detector was killed" in line]
        assert len(reports) == 1, reports
        assert system.proc.poll() is None  # not required: the rest runs on


SECOND_NAVIGATOR = """
[[node]]
name = "navigator"
run = "navigator"
respawn = true
respawn_delay = 0.2
respawn_max = 0
"""


def test_a_second_navigator_that_finds_navigate_to_served_is_not_respawned(system, tmp_path):
    """Its exit 4 (a conflict) would be the same at every start."""
    path = tmp_path / "second.toml"
    path.write_text(SECOND_NAVIGATOR)
    second = subprocess.run(
        [*turtlectl(), "launch", str(path), "--connect", system.endpoint],
        capture_output=True,
        text=True,
        timeout=30,
        stdin=subprocess.DEVNULL,
        env={**os.environ, "TURTLECTL_LOG_DIR": str(tmp_path / "logs")},
    )
    out = second.stdout + second.stderr
    assert second.returncode == 1, out  # its every node has exited
    assert out.count("started navigator") == 1, out
    assert (
        "navigator exited with code 4 (could not start: another process already holds what it claims); "
        "not respawning: respawning cannot help"
    ) in out
    assert "already serves navigate_to" in out
    assert "ready in" not in out, out  # the running system's navigator is not the one started here


NEVER_STARTS = textwrap.dedent(
    """
    import msgspec

    from turtlectl import Node


    class PatrolParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
        side: float = 2.0


    class Patrol:
        Params = PatrolParams

        def __init__(self, node: Node[PatrolParams]):
            raise RuntimeError("the patrol cannot start")
    """
)

WITH_A_NODE_THAT_NEVER_STARTS = """
[[node]]
name = "sim"
run = "sim"
[[node]]
name = "status_monitor"
run = "status_monitor"
[[node]]
name = "patrol"
run = "./patrol.py:Patrol"
respawn = true
"""


def test_a_node_whose_constructor_always_raises_hits_its_start_limit_and_the_launch_says_so(tmp_path):
    """A student's node that raised in its constructor was respawned 1+2+4+8+16 s with its
    traceback printed six times, the launch said "3 of 4 nodes ready in 33.21 s", and Ctrl-C
    then exited 0."""
    (tmp_path / "patrol.py").write_text(NEVER_STARTS)
    (tmp_path / "launch.toml").write_text(WITH_A_NODE_THAT_NEVER_STARTS)
    began = time.monotonic()
    with running_system(tmp_path / "launch.toml", ready=("sim", "status_monitor"), cwd=tmp_path) as system:
        system.wait_line(r"patrol failed \d+ starts in a row", 30.0)
        given_up_after = time.monotonic() - began
        out = system.output()
        error = "RuntimeError: the patrol cannot start"
        assert out.count("Traceback") == 1, out  # its output on the terminal for the first start only
        ready = re.search(r"2 of 3 nodes ready in (\S+) s \(since turtlectl started\); patrol never started: (.*)", out)
        assert ready and ready[2] == error, out
        assert float(ready[1]) < 10.0, out  # not after its respawns: the others were ready long before
        given_up = re.search(
            rf"patrol failed 3 starts in a row \(start_tries = 3\), each exiting before it was ready; "
            rf"not respawning it; last: exited with code 1: {error}; full log: (\S+)$",
            out,
            re.MULTILINE,
        )
        assert given_up, out
        assert Path(given_up[1]).read_text().count("Traceback") == 3  # every start's output is in its log
        assert given_up_after < 20.0, out  # a backoff without a start limit would take 33 s and never give up
        assert system.stop(signal.SIGINT) == 1
        assert "stopped (received SIGINT; patrol never started); exit code 1" in system.all_output()
