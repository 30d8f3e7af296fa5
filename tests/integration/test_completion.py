"""Shell completion offers the running system's names: topics, nodes, turtles, parameters,
services and goal services, through the shell's own protocol (Click's COMP_WORDS / COMP_CWORD, as
the script `turtlectl --install-completion` installs calls it); nothing, silently, without a system."""

from __future__ import annotations

import os
import subprocess

import pytest

from tests.integration.harness import free_port, turtlectl

pytestmark = pytest.mark.integration


def completions(endpoint: str, *words: str) -> tuple[list[str], str]:
    """What bash is offered for the last of ``words`` (the command line up to the cursor)."""
    env = dict(os.environ, _TURTLECTL_COMPLETE="complete_bash", COMP_WORDS=" ".join(["turtlectl", *words]))
    env["COMP_CWORD"] = str(len(words))
    env["TURTLECTL_CONNECT"] = endpoint
    done = subprocess.run(turtlectl(), env=env, capture_output=True, text=True, timeout=30, stdin=subprocess.DEVNULL)
    return done.stdout.split(), done.stderr


@pytest.mark.parametrize(
    ("words", "offered"),
    [
        (("echo", "ro"), ["robot/status"]),
        (("echo", "turtle1/"), ["turtle1/cmd_vel", "turtle1/pose"]),
        (("hz", "robot/status", "obs"), ["obstacles"]),
        (("param", "get", "nav"), ["navigator"]),
        (("param", "get", "navigator", "goal_t"), ["goal_timeout"]),
        (("goto", "--turtle", "tur"), ["turtle1"]),
        (("log", "--node", "s"), ["sim", "status_monitor"]),
        (("action", "send-goal", "nav"), ["navigate_to"]),
        (("call", "res"), ["reset"]),
    ],
)
def test_live_names_are_offered(system, words, offered):
    got, err = completions(system.endpoint, *words)
    assert got == offered, (got, err)


def test_the_runtime_s_own_keys_only_when_asked_for(system):
    got, _ = completions(system.endpoint, "call", "")
    assert "reset" in got and not any(key.startswith("turtlectl/") for key in got), got
    got, _ = completions(system.endpoint, "call", "turtlectl/params/nav")
    assert "turtlectl/params/navigator" in got, got


def test_without_a_system_nothing_is_offered_and_nothing_said():
    got, err = completions(f"tcp/127.0.0.1:{free_port()}", "echo", "ro")
    assert got == [] and err == ""
