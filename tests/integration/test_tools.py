"""Operator tools against the real running system: list, hz, echo, pub, call, run, view."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time

import pyte
import pytest

from tests.integration.harness import NODES, pump, running_system, set_winsize, turtlectl, view_in_pty
from turtlectl.messages import TurtleStatus
from turtlectl.messages.keys import GRAPH, STATUS
from turtlectl.runtime.client import services
from turtlectl.runtime.client.errors import ExitCode, TurtlectlError, exit_code

pytestmark = pytest.mark.integration


def graph_keys(system) -> list[str]:
    return [str(r.ok.key_expr) for r in system.session.liveliness().get(GRAPH, timeout=2.0) if r.ok is not None]


def test_list_shows_the_live_graph(system):
    result = system.run_cli("list", "--json")
    assert result.returncode == 0, result.stderr
    graph = json.loads(result.stdout)
    nodes = {n["name"]: n for n in graph["nodes"]}
    assert set(nodes) == set(NODES)
    assert {name: n["pid"] for name, n in nodes.items()} == system.alive
    assert all(n["host"] and n["uptime"] > 0 for n in nodes.values())
    topics = {t["key"]: t for t in graph["topics"]}
    assert topics["turtle1/pose"]["type"] == "turtlectl/Pose" and topics["turtle1/pose"]["publishers"] == ["sim"]
    assert set(topics["turtle1/pose"]["subscribers"]) == {"navigator", "obstacle_detector", "status_monitor"}
    assert topics["turtle1/cmd_vel"] == {
        "key": "turtle1/cmd_vel",
        "type": "turtlectl/Twist",
        "publishers": ["navigator"],
        "subscribers": ["sim"],
    }
    services = {s["key"]: s for s in graph["services"]}
    assert services["reset"]["servers"] == ["sim", "status_monitor"]
    assert services["navigate_to"]["type"] == "turtlectl/NavigateToRequest"
    text = system.run_cli("list").stdout
    assert "NODES" in text and "turtle1/pose" in text and "served by navigator" in text


def test_a_killed_node_leaves_the_list_within_a_second(system):
    pid = system.alive["obstacle_detector"]  # respawns: the system is whole again afterwards
    os.kill(pid, signal.SIGKILL)
    killed = time.monotonic()
    while any(f"/{pid}/" in k or k.endswith(f"/{pid}") for k in graph_keys(system)):
        assert time.monotonic() - killed < 1.0, "still listed a second after SIGKILL"
    system.wait_until(lambda: system.alive.get("obstacle_detector", pid) != pid, 10.0, "obstacle_detector back")


def test_hz_reports_our_rates_within_one_percent(system):
    result = system.run_cli("hz", "robot/status", "obstacles", "turtle1/pose", "--duration", "6", "--json", timeout=30)
    assert result.returncode == 0, result.stderr
    last = {}
    for line in result.stdout.splitlines():
        stats = json.loads(line)
        last[stats["key"]] = stats
    for key, rate in (("robot/status", 10.0), ("obstacles", 5.0), ("turtle1/pose", 62.5)):
        assert abs(last[key]["rate"] - rate) <= 0.01 * rate, last[key]
        assert abs(last[key]["publisher_rate"] - rate) <= 0.01 * rate, last[key]


def test_hz_against_a_publisher_of_known_rate(system):
    publisher = subprocess.Popen(
        [
            *turtlectl(),
            "pub",
            "bench/known",
            '{"linear": 0.0}',
            "--type",
            "Twist",
            "--rate",
            "20",
            "--connect",
            system.endpoint,
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        result = system.run_cli("hz", "bench/known", "--duration", "5", "--json", timeout=30)
        stats = json.loads(result.stdout.splitlines()[-1])
        assert abs(stats["rate"] - 20.0) <= 0.2 and abs(stats["publisher_rate"] - 20.0) <= 0.2, stats
    finally:
        publisher.send_signal(signal.SIGINT)
        publisher.wait(5)


def test_echo_field_csv_and_short_arrays(system):
    battery = system.run_cli("echo", "robot/status", "--field", "battery", "--count", "2")
    assert battery.returncode == 0 and all(0 < float(v) <= 100 for v in battery.stdout.split())
    csv = system.run_cli("echo", "robot/status", "--csv", "--count", "3").stdout.splitlines()
    assert csv[0] == "x,y,theta,vel_x,vel_y,battery,stamp,seq" and len(csv) == 4
    short = system.run_cli("echo", "obstacles", "--once").stdout
    assert "... (72 values)]" in short
    full = system.run_cli("echo", "obstacles", "--once", "--full").stdout
    assert "..." not in full
    first_beam = system.run_cli("echo", "obstacles", "--once", "--field", "ranges.0")
    assert first_beam.returncode == 0 and float(first_beam.stdout) > 0
    missing = system.run_cli("echo", "robot/status", "--once", "--field", "speed")
    assert missing.returncode == 2 and "TurtleStatus has no field 'speed'" in missing.stderr
    slash = system.run_cli("echo", "/robot/status", "--once", "--json")  # ROS habit: leading slash
    assert slash.returncode == 0 and json.loads(slash.stdout)["type"] == "turtlectl/TurtleStatus"
    bad = system.run_cli("echo", "robot//status", "--once")
    assert bad.returncode == 2 and "not a valid key expression" in bad.stderr


def test_echo_survives_a_publisher_restart(system):
    echo = subprocess.Popen(
        [*turtlectl(), "echo", "robot/status", "--field", "seq", "--count", "40", "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert echo.stdout is not None
    first = echo.stdout.readline()  # echo is receiving
    assert first.strip().isdigit()
    old = system.alive["status_monitor"]
    os.kill(old, signal.SIGKILL)
    system.wait_until(lambda: system.alive.get("status_monitor", old) != old, 10.0, "status_monitor back")
    out, _ = echo.communicate(timeout=20)
    seqs = [int(first)] + [int(v) for v in out.split()]
    assert len(seqs) == 40 and any(b < a for a, b in zip(seqs, seqs[1:], strict=False)), "no restart of seq seen"


def test_pub_twist_moves_the_turtle_and_checks_fields(system):
    system.teleport(3.0, 3.0, 0.0)
    result = system.run_cli("pub", "turtle1/cmd_vel", '{"linear": 1.0}', "--rate", "20", "--times", "10")
    assert result.returncode == 0 and "published 10 turtlectl/Twist" in result.stderr
    moved = system.latest_pose()
    assert moved.x > 3.2
    for payload, message in (
        ('{"linear": "fast"}', "linear: Expected `float`, got `str`"),
        ('{"speed": 1}', "unknown field `speed`"),
        ("{", "not valid JSON"),
    ):
        bad = system.run_cli("pub", "turtle1/cmd_vel", payload)
        assert bad.returncode == 2 and message in bad.stderr, bad.stderr
    unknown = system.run_cli("pub", "some/topic", "{}")
    assert unknown.returncode == 2 and "--type" in unknown.stderr


def test_call_any_service(system):
    teleport = system.run_cli("call", "turtle1/teleport_absolute", '{"x": 2, "y": 2, "theta": 0}', "--json")
    assert teleport.returncode == 0 and json.loads(teleport.stdout)["detail"].startswith("teleported to (2, 2")
    params = system.run_cli("call", "turtlectl/params/navigator")
    assert params.returncode == 0 and json.loads(params.stdout)["position_tolerance"] == 0.01
    missing = system.run_cli("call", "no/such/service")
    assert missing.returncode == 3 and "nothing serves no/such/service" in missing.stderr, missing.stderr
    started = time.monotonic()  # the wait itself, in this process: not the CLI's start-up
    with pytest.raises(TurtlectlError) as err:
        list(services.call_service(system.endpoint, "", "no/such/service", b"{}", 5.0))
    assert exit_code(err.value) == ExitCode.UNREACHABLE and time.monotonic() - started < 3.0
    bad = system.run_cli("call", "turtle1/teleport_absolute", '{"x": 2}')
    assert bad.returncode == 2 and "missing required field `y`" in bad.stderr


def test_every_command_has_an_example_in_its_help():
    for command in (
        "launch",
        "goto",
        "cancel",
        "teleport",
        "reset",
        "echo",
        "list",
        "hz",
        "pub",
        "call",
        "run",
        "view",
    ):
        result = subprocess.run([*turtlectl(), command, "--help"], capture_output=True, text=True, timeout=20)
        assert result.returncode == 0 and "Example: turtlectl " + command in " ".join(result.stdout.split())


NO_NAVIGATOR = """
[[node]]
name = "sim"
run = "sim"
[[node]]
name = "navigator"
run = "navigator"
[node.params]
goal_timeout = 20.0
"""


def test_run_one_node_in_the_foreground_with_overrides(tmp_path):
    file = tmp_path / "system.toml"
    file.write_text(NO_NAVIGATOR)
    only_sim = tmp_path / "only_sim.toml"
    only_sim.write_text('[[node]]\nname = "sim"\nrun = "sim"\n')
    with running_system(only_sim, ready=("sim",)) as system:
        bad = system.run_cli("run", "navigator", "--file", str(file), "-p", "goal_timeout=-1")
        assert bad.returncode == 2 and "--param navigator.goal_timeout must be >= 0.1" in bad.stderr
        node = subprocess.Popen(
            [
                *turtlectl(),
                "run",
                "navigator",
                "--file",
                str(file),
                "-p",
                "goal_timeout=60",
                "-p",
                "gains.k_linear=25",
                "--connect",
                system.endpoint,
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        try:
            system.wait_until(lambda: "navigator" in system.alive, 20.0, "navigator from turtlectl run")
            params = json.loads(system.run_cli("call", "turtlectl/params/navigator").stdout)
            assert params["goal_timeout"] == 60.0 and params["gains"]["k_linear"] == 25.0
            goal = system.run_cli("goto", "4", "4", "0")
            assert goal.returncode == 0, goal.stdout + goal.stderr
            node.send_signal(signal.SIGINT)
            assert node.wait(10) == 0
            system.wait_until(lambda: "navigator" not in system.alive, 5.0, "navigator gone")
        finally:
            node.kill()


def test_view_draws_the_world_in_a_real_terminal(system):
    system.teleport(3.0, 8.0, 0.0)  # facing +x: the arrow is →
    pid, fd = view_in_pty(system.endpoint)
    screen = pyte.Screen(100, 30)
    stream = pyte.ByteStream(screen)
    try:
        set_winsize(fd, 30, 100)
        os.kill(pid, signal.SIGWINCH)
        deadline = time.monotonic() + 15
        while "battery" not in "\n".join(screen.display):
            assert time.monotonic() < deadline, "\n".join(screen.display)
            assert pump(fd, stream, 0.2)
        shown = "\n".join(screen.display)
        assert screen.display[0].startswith("+---") and "|" in screen.display[5]
        assert "→" in shown and "x  3.00 y  8.00 heading   0.0 deg" in shown
        assert shown.count("o") > 5  # the launch file's obstacles
        screen.resize(20, 60)
        set_winsize(fd, 20, 60)
        os.kill(pid, signal.SIGWINCH)
        pump(fd, stream, 1.0)
        assert screen.display[0].startswith("+---") and screen.display[0].rstrip().endswith("+"), "\n".join(
            screen.display
        )
        assert len(screen.display[0].rstrip()) < 60
        os.write(fd, b"q")
        start = time.monotonic()
        while pump(fd, stream, 0.1) and time.monotonic() - start < 5:
            pass
        _, status = os.waitpid(pid, 0)
        assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0
    finally:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        os.close(fd)


def test_echo_with_a_wildcard_says_which_key(system):
    result = system.run_cli("echo", "turtle1/*", "--count", "3")
    assert result.returncode == 0 and "# turtlectl/Pose on turtle1/pose" in result.stdout


def test_a_second_process_with_a_node_s_name_refuses_to_start(system):
    """The second one refuses to start: beside the first, two status monitors would alternate on
    robot/status."""
    node = subprocess.run(
        [*turtlectl(), "run", "status_monitor", "--connect", system.endpoint],
        capture_output=True,
        text=True,
        timeout=30,
        stdin=subprocess.DEVNULL,
    )
    assert node.returncode == 4 and "already publishes robot/status" in node.stderr, node.stderr
    system.collect(STATUS, TurtleStatus, 3, timeout=5.0)  # the system's own goes on


def test_param_list_get_and_dump_read_what_the_node_runs_with(system):
    """`turtlectl param` against the real system; dump reads back as the launch file's table."""
    import tomllib

    from tests.integration.harness import DEFAULT_LAUNCH
    from turtlectl.cli.system.launchfile import load_launch

    listed = system.run_cli("param", "list", "navigator", "--json")
    assert listed.returncode == 0, listed.stderr
    assert "goal_timeout" in json.loads(listed.stdout) and "gains.lookahead" in json.loads(listed.stdout)
    got = system.run_cli("param", "get", "navigator", "robot_radius")
    assert (got.returncode, got.stdout.strip()) == (0, "0.3"), got
    dumped = system.run_cli("param", "dump", "obstacle_detector")
    assert dumped.returncode == 0, dumped.stderr
    launched = load_launch(DEFAULT_LAUNCH).params["obstacle_detector"]
    table = tomllib.loads(dumped.stdout)
    assert all(table[k] == v for k, v in launched.items()), (table, launched)
    unknown = system.run_cli("param", "get", "navigator", "nope")
    assert unknown.returncode == ExitCode.BAD_INPUT and "has no parameter 'nope' (it has: " in unknown.stderr
    nobody = system.run_cli("param", "list", "nobody")
    assert nobody.returncode == ExitCode.UNREACHABLE, nobody
    assert (
        "no node named 'nobody' answers (running: navigator, obstacle_detector, sim, status_monitor)" in nobody.stderr
    )
