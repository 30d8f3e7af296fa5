"""cli.supervisor.process without starting anything: the one command a node is started with."""

from __future__ import annotations

import sys

from cli.launchfile import node_config, parse_launch
from cli.supervisor.process import node_command
from nodes.kinds import KINDS
from runtime.config import ENV_VAR, SUPERVISOR_PID_VAR, decode_config

PLAN = parse_launch('[[node]]\nname = "nav"\nrun = "navigator"\n')


def test_a_supervised_node_runs_its_kind_s_module_unbuffered_and_knows_its_supervisor():
    config = node_config(PLAN, "nav", "tcp/127.0.0.1:7447", domain="lab1")
    argv, env = node_command(config, supervisor_pid=4242)
    assert argv == [sys.executable, "-u", "-m", KINDS["navigator"].module]
    assert decode_config(env[ENV_VAR]) == config
    assert env[SUPERVISOR_PID_VAR] == "4242" and env["PYTHONUNBUFFERED"] == "1"


def test_a_node_run_on_its_own_watches_no_supervisor_even_one_inherited(monkeypatch):
    monkeypatch.setenv(SUPERVISOR_PID_VAR, "99")  # `turtlectl run` typed in a node's shell
    monkeypatch.setenv("TURTLECTL_TEST_MARK", "kept")
    config = node_config(PLAN, "nav", "tcp/127.0.0.1:7447")
    argv, env = node_command(config)
    assert argv[-1] == KINDS["navigator"].module
    assert SUPERVISOR_PID_VAR not in env and env["TURTLECTL_TEST_MARK"] == "kept"
