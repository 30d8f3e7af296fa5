"""The client tools' rules against the real system: `call` follows goto's (streams replies,
holds a client token, a timeout cancels the goal, an answer that says no is exit 1); one
Ctrl-C rule; messages that say what to do next; domains on one router seen from outside;
the router lost mid-goal; the progress line within 80 columns; the view's keys; and the
raw client of docs/interfaces.md."""

from __future__ import annotations

import json
import math
import os
import pty
import re
import select
import signal
import subprocess
import sys
import time

import pyte
import pytest

from tests.integration.harness import (
    ROOT,
    Router,
    free_port,
    pump,
    read_until_closed,
    running_system,
    set_winsize,
    turtlectl,
    view_in_pty,
)
from turtlectl.messages import Twist

pytestmark = pytest.mark.integration


STARTED: list[subprocess.Popen] = []


@pytest.fixture(autouse=True)
def _kill_background_commands():
    """Whatever a test asserts, the commands it started in the background do not outlive it."""
    yield
    while STARTED:
        proc = STARTED.pop()
        if proc.poll() is None:
            proc.kill()
            proc.wait(5)


def cli(system, *args: str) -> subprocess.Popen:
    """A turtlectl command against ``system``, running in the background (killed after the test)."""
    domain = ("--domain", system.domain) if system.domain else ()
    proc = subprocess.Popen(
        [*turtlectl(), *domain, *args, "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        text=True,
    )
    STARTED.append(proc)
    return proc


def read_line(stream, timeout: float) -> str:
    """The next line of a pipe, waited for under a deadline (an event, not a sleep)."""
    ready, _, _ = select.select([stream], [], [], timeout)
    assert ready, f"no line within {timeout} s"
    return stream.readline()


# -- call follows goto's rules -------------------------------------------------------


def test_call_navigate_to_prints_each_reply_as_it_arrives(system):
    system.teleport(1.0, 5.5, 0.0)
    call = cli(system, "call", "navigate_to", '{"x": 10, "y": 5.5, "theta": 0}', "--json")
    first = json.loads(read_line(call.stdout, 10.0))
    first_at = time.monotonic()
    assert first["type"] == "turtlectl/NavigateToFeedback"
    rest, err = call.communicate(timeout=20)
    ended_at = time.monotonic()
    assert call.returncode == 0, err
    assert ended_at - first_at > 0.5, "the feedback came only with the outcome"
    last = json.loads(rest.splitlines()[-1])
    assert last["type"] == "turtlectl/NavigateToResponse" and last["success"]


def test_call_navigate_to_timeout_after_feedback_cancels_the_goal(system):
    system.teleport(1.0, 5.5, 0.0)
    start = len(system.lines)
    result = system.run_cli("call", "navigate_to", '{"x": 10, "y": 5.5, "theta": 0}', "--timeout", "1")
    assert result.returncode == 1, result.stderr
    assert "did not end within --timeout 1 s; the navigator canceled the goal" in result.stderr
    assert "NavigateToFeedback" in result.stdout and "did not answer" not in result.stderr
    system.wait_line(r"navigator .*goal failed .*: canceled", 5.0, start)  # its cancel, confirmed
    assert system.wait_stopped().x < 9.0


def test_ctrl_c_on_call_cancels_the_goal_and_exits_130(system):
    system.teleport(1.0, 5.5, 0.0)
    start = len(system.lines)
    call = cli(system, "call", "navigate_to", '{"x": 10, "y": 5.5, "theta": 0}')
    system.wait_moving()
    call.send_signal(signal.SIGINT)
    _, err = call.communicate(timeout=10)
    assert call.returncode == 130 and "interrupted: the navigator canceled the goal" in err
    system.wait_line(r"navigator .*goal failed .*: canceled", 5.0, start)


def test_call_exits_1_when_the_answer_says_no_and_2_for_an_invalid_goal(system):
    cancel = system.run_cli("call", "navigate_to/cancel")
    assert cancel.returncode == 1 and "ok: false" in cancel.stdout
    refused = system.run_cli("call", "navigate_to", '{"x": 50, "y": 1, "theta": 0}')
    assert refused.returncode == 2 and "refused: true" in refused.stdout  # invalid goal: as a teleport there
    teleport = system.run_cli("teleport", "5", "5", "0")
    walled = system.run_cli("call", "navigate_to", '{"x": 9, "y": 9, "theta": 0}')  # inside the obstacle at (9, 9)
    assert teleport.returncode == 0 and walled.returncode == 2 and "inside an obstacle" in walled.stdout
    assert system.run_cli("cancel").returncode == 1  # the same rule as cancel's


def test_a_known_key_keeps_its_type_and_wildcard_json_names_keys(system):
    wrong = system.run_cli("pub", "turtle1/cmd_vel", '{"x": 1, "y": 1, "theta": 0}', "--type", "Pose")
    assert wrong.returncode == 2 and "turtle1/cmd_vel carries turtlectl/Twist, not turtlectl/Pose" in wrong.stderr
    lines = system.run_cli("echo", "**", "--json", "--count", "5").stdout.splitlines()
    assert len(lines) == 5 and all(json.loads(line)["key"] for line in lines), lines


def test_teleport_answers_in_degrees(system):
    result = system.run_cli("teleport", "2", "2", "45")
    assert result.returncode == 0 and result.stdout.strip() == "teleported to (2, 2, 45 deg)", result.stdout


# -- one Ctrl-C rule ---------------------------------------------------------------------


@pytest.mark.parametrize(
    "args",
    [
        ("echo", "robot/status"),
        ("hz", "robot/status"),
        ("pub", "test/ctrl_c", '{"linear": 0}', "--type", "Twist", "--rate", "20"),
    ],
    ids=["echo", "hz", "pub --rate"],
)
def test_ctrl_c_ends_a_command_that_runs_until_stopped_with_0(system, args):
    proc = cli(system, *args)
    if args[0] == "pub":
        system.collect("test/ctrl_c", Twist, 1, timeout=10.0)  # it is publishing
    else:
        read_line(proc.stdout, 10.0)  # it is printing
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=10)
    assert proc.returncode == 0, err
    assert "Traceback" not in err


@pytest.mark.parametrize(
    "args",
    [("echo", "robot/status", "--once", "--field", "x"), ("call", "navigate_to/cancel"), ("teleport", "3", "3", "0")],
    ids=["echo --once", "call", "teleport"],
)
def test_ctrl_c_once_the_result_is_printed_changes_nothing(system, args):
    """Ctrl-C within ~0.1 s after a one-shot command printed its result: no exit 130, no "Exception
    ignored ... KeyboardInterrupt", no SIGABRT (134)."""
    expected = 1 if args[0] == "call" else 0  # cancel with no goal running: an answer that says no
    for _ in range(4):
        proc = cli(system, *args)
        read_line(proc.stdout, 10.0)  # the result is out
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=10)
        assert proc.returncode == expected, err
        assert "Traceback" not in err and "Exception" not in err and "FATAL" not in err, err


def test_help_and_exit_codes_state_the_ctrl_c_rule():
    text = " ".join(subprocess.run([*turtlectl(), "--help"], capture_output=True, text=True, timeout=20).stdout.split())
    assert "Ctrl-C on a command that runs until stopped (echo, hz, view, pub --rate)" in text
    assert "130 interrupted by Ctrl-C before its result (goto, call" in text


# -- messages that say what to do next --------------------------------------------------


def test_echo_of_feedback_without_a_goal_says_when_it_is_published(system):
    result = system.run_cli("echo", "navigate_to/feedback", "--timeout", "4")
    assert result.returncode == 3
    assert "navigator publishes it only while a goal runs" in result.stderr and "launch` running" not in result.stderr


def test_hz_on_a_silent_topic_says_so_and_ctrl_c_exits_0(system):
    hz = cli(system, "hz", "nosuch")
    line = read_line(hz.stderr, 10.0)
    assert "nothing published on nosuch yet: no running node publishes it" in line
    hz.send_signal(signal.SIGINT)
    hz.communicate(timeout=10)
    assert hz.returncode == 0


def test_no_router_is_reported_at_once():
    for args in (("view",), ("goto", "1", "1", "0"), ("list",)):
        started = time.monotonic()
        result = subprocess.run(
            [*turtlectl(), *args, "--connect", f"tcp/127.0.0.1:{free_port()}"],
            capture_output=True,
            text=True,
            timeout=20,
        )
        assert result.returncode == 3 and "no turtlectl system at" in result.stderr, (args, result.stderr)
        assert time.monotonic() - started < 2.0, args  # Zenoh alone would retry for 2.5 s


# -- the live progress line and the view in real terminals -------------------------------


def test_goto_progress_fits_an_80_column_terminal(system):
    system.teleport(1.0, 5.5, 0.0)
    master, slave = pty.openpty()
    set_winsize(slave, 24, 80)
    env = {k: v for k, v in os.environ.items() if k not in ("LINES", "COLUMNS")}
    goto = subprocess.Popen(
        [*turtlectl(), "goto", "10", "5.5", "-45", "--connect", system.endpoint], stdout=slave, stderr=slave, env=env
    )
    STARTED.append(goto)
    os.close(slave)
    out = read_until_closed(master)
    assert goto.wait(10) == 0, out
    updates = [u for u in out.decode().split("\r\x1b[K") if u.strip()][:-1]  # the last one is the outcome
    assert len(updates) > 5, out
    assert all(len(u) <= 79 for u in updates), max(updates, key=len)
    reached = re.search(r"reached at \(([\d.]+), ([\d.]+), ([\d.]+) deg\)", out.decode())
    assert reached, out
    x, y, theta = (float(v) for v in reached.groups())
    assert math.hypot(x - 10.0, y - 5.5) <= 0.01 and abs(theta - 315.0) <= 0.5, out  # the tolerances


def _trail_dots(screen: pyte.Screen) -> int:
    rows = screen.display
    map_rows = [r for r in rows[1:] if r.startswith("|")]
    return sum(r.count(".") for r in map_rows)


def test_view_has_a_legend_c_clears_the_trail_and_ctrl_c_exits_0(system):
    system.teleport(2.0, 5.5, 0.0)
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
        assert "o obstacle  * scan hit  . trail  + path  X goal  (c clears the trail)" in "\n".join(screen.display)
        assert system.run_cli("goto", "8", "5.5", "0").returncode == 0  # a trail behind the turtle
        deadline = time.monotonic() + 5
        while _trail_dots(screen) < 5:
            assert time.monotonic() < deadline, "\n".join(screen.display)
            assert pump(fd, stream, 0.1)
        os.write(fd, b"c")
        deadline = time.monotonic() + 5
        while _trail_dots(screen) > 1:  # the turtle is at rest: at most the cell it stands on comes back
            assert time.monotonic() < deadline, "\n".join(screen.display)
            assert pump(fd, stream, 0.1)
        os.kill(pid, signal.SIGINT)
        while pump(fd, stream, 0.1):
            pass
        _, status = os.waitpid(pid, 0)
        assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0
    finally:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        os.close(fd)


# -- the raw client of docs/interfaces.md ------------------------------------------------


def test_the_raw_client_of_the_interface_reference_runs(system):
    result = subprocess.run(
        [sys.executable, str(ROOT / "docs" / "examples" / "raw_client.py"), system.endpoint],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    out = result.stdout
    assert out.startswith("4 nodes: navigator (pid ") and "teleport: {'type': 'turtlectl/Ack', 'ok': True" in out
    assert re.search(r"goal reached in [\d.]+ s after \d+ feedback replies", out), out
    assert "reset: 2 acks: turtle back at its spawn pose; turtle1: battery full" in out
    assert "cancel: ok=False (no goal is running)" in out


# -- a router shared by domains; the router lost mid-goal ----------------------------------


@pytest.fixture()
def router():
    r = Router()
    r.start()
    yield r
    r.kill()


def plain(*args: str, endpoint: str) -> subprocess.CompletedProcess[str]:
    """A command outside any domain."""
    env = {k: v for k, v in os.environ.items() if k != "TURTLECTL_DOMAIN"}
    return subprocess.run(
        [*turtlectl(), *args, "--connect", endpoint], capture_output=True, text=True, timeout=30, env=env
    )


def test_a_client_without_domain_sees_every_domain_and_is_told_which_to_use(router):
    with (
        running_system(join=router.endpoint, domain="alpha") as alpha,
        running_system(join=router.endpoint, domain="beta", ready=("sim",), extra_args=("--only", "sim")),
    ):
        graph = json.loads(plain("list", "--json", endpoint=router.endpoint).stdout)
        names = {n["name"] for n in graph["nodes"]}
        assert {f"alpha:{n}" for n in alpha.alive} | {"beta:sim"} == names
        assert graph["domains"] == ["alpha", "beta"]
        topics = {t["key"]: t for t in graph["topics"]}
        assert topics["alpha/robot/status"]["publishers"] == ["alpha:status_monitor"]
        text = plain("list", endpoint=router.endpoint).stdout
        assert "alpha:navigator" in text and "DOMAINS" in text

        lost = plain("goto", "3", "3", "0", endpoint=router.endpoint)
        assert lost.returncode == 3
        assert (
            "nothing serves navigate_to" in lost.stderr
            and "add it before the command, `turtlectl --domain alpha ...`" in lost.stderr
        )
        wrong = plain("--domain", "beta", "goto", "3", "3", "0", endpoint=router.endpoint)
        assert (
            wrong.returncode == 3
            and "in domain beta" in wrong.stderr
            and "add it before the command, `turtlectl --domain alpha ...`" in wrong.stderr
        )
        empty = plain("--domain", "gamma", "list", endpoint=router.endpoint).stdout
        assert (
            "(none: systems run in domains alpha, beta on this router: add it before the command, `turtlectl --domain alpha ...`)"
            in empty
        )

        status = plain("echo", "alpha/robot/status", "--once", "--json", endpoint=router.endpoint)
        assert status.returncode == 0 and json.loads(status.stdout)["type"] == "turtlectl/TurtleStatus"
        silent = plain("echo", "robot/status", "--timeout", "4", endpoint=router.endpoint)
        assert (
            silent.returncode == 3
            and "published in domain alpha: add it before the command, `turtlectl --domain alpha ...`" in silent.stderr
        )
        # a goal reached from outside the domain still holds the caller's token inside it
        alpha.teleport(1.0, 5.5, 0.0)
        start = len(alpha.lines)
        timed_out = plain(
            "call", "alpha/navigate_to", '{"x": 10, "y": 5.5, "theta": 0}', "--timeout", "1", endpoint=router.endpoint
        )
        assert timed_out.returncode == 1, timed_out.stderr
        assert "the navigator canceled the goal" in timed_out.stderr  # alpha/navigate_to/cancel answered
        alpha.wait_line(r"navigator .*goal failed .*: canceled", 5.0, start)


def test_the_router_lost_mid_goal_is_not_blamed_on_the_navigator(router):
    with running_system(join=router.endpoint) as system:
        system.teleport(1.0, 5.5, 0.0)
        goto = cli(system, "goto", "10", "5.5", "0")
        system.wait_moving()
        router.kill()
        _, err = goto.communicate(timeout=10)
        assert goto.returncode == 3, err
        assert f"lost the router at {router.endpoint} before the goal ended" in err and "navigator" not in err
