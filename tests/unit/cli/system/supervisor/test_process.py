"""cli.system.supervisor.process: the one command a node is started with, and one supervised child
with real processes (signals reach its whole group)."""

from __future__ import annotations

import io
import os
import signal
import sys
import time

from turtlectl.cli.system.launchfile import parse_launch
from turtlectl.cli.system.overrides import node_config
from turtlectl.cli.system.supervisor.printer import Printer
from turtlectl.cli.system.supervisor.process import Child, node_command
from turtlectl.nodes.kinds import KINDS
from turtlectl.runtime.config import ENV_VAR, SUPERVISOR_PID_VAR, decode_config

PLAN = parse_launch('[[node]]\nname = "nav"\nrun = "navigator"\n')


def test_a_supervised_node_runs_its_kind_s_module_unbuffered_and_knows_its_supervisor():
    config = node_config(PLAN, "nav", "tcp/127.0.0.1:7447", domain="lab1")
    argv, env = node_command(config, supervisor_pid=4242)
    assert argv == [sys.executable, "-u", "-m", KINDS["navigator"].module]
    assert decode_config(env[ENV_VAR]) == config
    assert env[SUPERVISOR_PID_VAR] == "4242" and env["PYTHONUNBUFFERED"] == "1"


def test_a_node_s_own_clients_are_in_its_system_s_domain(monkeypatch):
    """The command line hands --domain to the nodes' configs, not to its own environment: a
    turtlectl.Client a node's code opens finds the domain in the node's environment."""
    monkeypatch.delenv("TURTLECTL_DOMAIN", raising=False)
    _, env = node_command(node_config(PLAN, "nav", "tcp/127.0.0.1:7447", domain="lab1"), supervisor_pid=1)
    assert env["TURTLECTL_DOMAIN"] == "lab1"
    _, env = node_command(node_config(PLAN, "nav", "tcp/127.0.0.1:7447"), supervisor_pid=1)
    assert "TURTLECTL_DOMAIN" not in env


def test_a_node_run_on_its_own_watches_no_supervisor_even_one_inherited(monkeypatch):
    monkeypatch.setenv(SUPERVISOR_PID_VAR, "99")  # `turtlectl run` typed in a node's shell
    monkeypatch.setenv("TURTLECTL_TEST_MARK", "kept")
    config = node_config(PLAN, "nav", "tcp/127.0.0.1:7447")
    argv, env = node_command(config)
    assert argv[-1] == KINDS["navigator"].module
    assert SUPERVISOR_PID_VAR not in env and env["TURTLECTL_TEST_MARK"] == "kept"


def test_a_signal_reaches_the_child_s_own_children_too(tmp_path):
    """The supervisor signals the child's process group, so a node's own children do not live on."""
    script = (
        "import subprocess, sys, time\n"
        # the processes under test only stay alive until the signal (not a wait for readiness)
        "grandchild = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(60)'])\n"  # pacing: ok
        "print(grandchild.pid, flush=True)\n"
        "time.sleep(60)\n"  # pacing: ok
    )
    printer = Printer(["parent"], stream=io.StringIO())
    child = Child("parent", [sys.executable, "-c", script], dict(os.environ), printer)
    child.start()
    try:
        deadline = time.monotonic() + 10
        while not printer.stream.getvalue().strip():
            assert time.monotonic() < deadline, "the child never printed its child's pid"
            child.flush_output(0.05)
        grandchild = int(printer.stream.getvalue().split("|")[-1])
        child.send(signal.SIGTERM)
        deadline = time.monotonic() + 5
        while child.running() or _alive(grandchild):
            assert time.monotonic() < deadline, "a SIGTERM to the child left its own child running"
            time.sleep(0.02)  # pacing: polling process state under a deadline
    finally:
        if child.proc is not None and child.proc.poll() is None:
            os.killpg(child.proc.pid, signal.SIGKILL)


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(") ", 1)[1][0] != "Z"
    except OSError:
        return False


def test_a_child_that_exits_takes_its_own_children_with_it():
    """A node that crashed (and was respawned) leaves nothing it had started running: signals go
    to the group even once the node itself is gone."""
    script = (
        "import subprocess, sys\n"
        "grandchild = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(60)'])\n"  # pacing: ok
        "print(grandchild.pid, flush=True)\n"
        "sys.exit(1)\n"
    )
    printer = Printer(["crasher"], stream=io.StringIO())
    child = Child("crasher", [sys.executable, "-c", script], dict(os.environ), printer)
    child.start()
    grandchild = None
    try:
        deadline = time.monotonic() + 10
        while child.poll() is None:
            assert time.monotonic() < deadline, "the child never exited"
            time.sleep(0.02)  # pacing: polling process state under a deadline
        child.flush_output()
        grandchild = int(printer.stream.getvalue().split("|")[-1])
        deadline = time.monotonic() + 5
        while _alive(grandchild):
            assert time.monotonic() < deadline, "the exited child's own child is still running"
            time.sleep(0.02)  # pacing: polling process state under a deadline
    finally:
        if grandchild is not None and _alive(grandchild):
            os.kill(grandchild, signal.SIGKILL)


def _run_to_the_end(child: Child) -> None:
    child.start()
    deadline = time.monotonic() + 10
    while child.poll() is None:
        assert time.monotonic() < deadline, "the child never exited"
        time.sleep(0.02)  # pacing: polling process state under a deadline
    child.flush_output()


def test_a_quiet_start_writes_the_node_s_output_to_its_log_only_and_keeps_its_last_line(tmp_path):
    """A start after one that failed before it was ready: its traceback was on the terminal once."""
    script = "print('starting'); print('RuntimeError: the patrol cannot start'); print()"
    terminal = io.StringIO()
    printer = Printer(["patrol"], stream=terminal)
    printer.log_to(tmp_path, ["patrol"])
    child = Child("patrol", [sys.executable, "-c", script], dict(os.environ), printer)
    _run_to_the_end(child)
    assert child.last_line == "RuntimeError: the patrol cannot start"  # the last line that is not blank
    child.quiet = True
    _run_to_the_end(child)
    assert terminal.getvalue().count("RuntimeError") == 1
    assert printer.log_path("patrol") == tmp_path / "patrol.log"
    assert (tmp_path / "patrol.log").read_text().count("RuntimeError: the patrol cannot start") == 2
