"""Against the real system: the parameter commands work on a node of a kind the
command line does not know (a user's own node, written with the runtime API and started by
hand beside a launched system), from what the node itself serves."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import pytest

from tests.integration.harness import ROOT, running_system
from turtlectl.runtime.client.errors import ExitCode
from turtlectl.runtime.config import ENV_VAR, NodeConfig, encode_config

pytestmark = pytest.mark.integration

#: a node kind of the user's own: nothing of turtlectl's tables knows 'patrol'
PATROL = textwrap.dedent(
    '''
    from typing import Annotated, ClassVar

    import msgspec

    from turtlectl.runtime import run_main


    class Gains(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
        """How it steers."""

        turn: Annotated[float, msgspec.Meta(gt=0.0)] = 1.5  # 1/s: how hard it turns to the next corner


    class PatrolParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
        """A square patrol."""

        speed: Annotated[float, msgspec.Meta(ge=0.0, le=2.0)] = 0.5  # m/s: how fast it drives
        laps: int = 3  # count: laps before it rests
        route: str = "square"  # -: the shape it drives
        gains: Gains = msgspec.field(default_factory=Gains)  # table: steering

        FIXED: ClassVar[dict[str, str]] = {"route": "the route is planned once, at start"}


    class Patrol:
        def __init__(self, node):
            node.on_params(lambda params: node.log.info("patrol now at %s m/s", params.speed))


    run_main(Patrol, PatrolParams)
    '''
)


@pytest.fixture
def patrol(system, tmp_path):
    """The patrol node, its own process, on the system's router (as a hand-written
    TURTLECTL_NODE_CONFIG starts it)."""
    module = tmp_path / "patrol.py"
    module.write_text(PATROL)
    config = NodeConfig(name="patrol", kind="patrol", connect=system.endpoint, params={"speed": 0.5})
    env = dict(os.environ, **{ENV_VAR: encode_config(config)}, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen(
        [sys.executable, str(module)], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    try:
        system.wait_until(lambda: "patrol" in system.alive or proc.poll() is not None, 30.0, "the patrol node")
        assert proc.poll() is None, proc.communicate()[1]
        yield proc
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def test_list_describe_set_and_get_work_on_a_node_kind_the_command_line_does_not_know(system, patrol):
    listed = system.run_cli("param", "list", "patrol", "--json")
    assert listed.returncode == 0, listed.stderr
    assert json.loads(listed.stdout) == ["speed", "laps", "route", "gains.turn"]

    described = system.run_cli("param", "describe", "patrol", "speed", "--json")
    assert described.returncode == 0, described.stderr
    info = json.loads(described.stdout)
    assert (info["type"], info["unit"], info["range"], info["default"], info["run_time"], info["value"]) == (
        "float",
        "m/s",
        "0 to 2",
        "0.5",
        True,
        0.5,
    )
    assert info["meaning"] == "how fast it drives"
    fixed = system.run_cli("param", "describe", "patrol", "route")
    assert fixed.returncode == 0, fixed.stderr
    assert "at run time: no: the route is planned once, at start" in fixed.stdout
    entry = json.loads(system.run_cli("param", "describe", "patrol", "gains.turn", "--json").stdout)
    assert (entry["unit"], entry["range"], entry["value"]) == ("1/s", "> 0", 1.5)

    changed = system.run_cli("param", "set", "patrol", "speed", "1.2")
    assert changed.returncode == 0, changed.stderr
    assert changed.stdout.strip() == "patrol speed = 1.2 (was 0.5)"
    assert json.loads(system.run_cli("param", "get", "patrol", "speed").stdout) == 1.2
    assert system.run_cli("param", "set", "patrol", "gains.turn", "2").returncode == 0
    assert json.loads(system.run_cli("param", "get", "patrol", "gains.turn").stdout) == 2.0
    now = json.loads(system.run_cli("param", "describe", "patrol", "speed", "--json").stdout)
    assert now["value"] == 1.2  # described as it runs now

    too_fast = system.run_cli("param", "set", "patrol", "speed", "5")
    assert too_fast.returncode == ExitCode.BAD_INPUT, too_fast.stderr
    assert too_fast.stderr.splitlines() == [
        "turtlectl: error: patrol: speed must be <= 2 (got 5)"
    ]  # as built-ins say it
    route = system.run_cli("param", "set", "patrol", "route", "circle")
    assert route.returncode == ExitCode.BAD_INPUT
    assert "cannot change while patrol runs: the route is planned once, at start" in route.stderr, route.stderr
    typo = system.run_cli("param", "set", "patrol", "sped", "1")
    assert typo.returncode == ExitCode.BAD_INPUT and "did you mean speed?" in typo.stderr, typo.stderr
    table = system.run_cli("param", "set", "patrol", "gains", "1")
    assert table.returncode == ExitCode.BAD_INPUT and "is a table: set one of its entries (gains.turn)" in table.stderr
    assert json.loads(system.run_cli("param", "get", "patrol", "speed").stdout) == 1.2  # nothing refused changed it

    dumped = system.run_cli("param", "dump", "patrol")
    assert dumped.returncode == 0 and "speed = 1.2" in dumped.stdout and "gains = { turn = 2.0 }" in dumped.stdout
    everyone = json.loads(system.run_cli("param", "list", "--json").stdout)
    assert "patrol" in everyone and "navigator" in everyone
    # the built-in nodes keep the launch file's checks beside it
    slow_scan = system.run_cli("param", "set", "obstacle_detector", "rate", "0.5")
    assert slow_scan.returncode == ExitCode.BAD_INPUT and "is not longer than the scan period" in slow_scan.stderr


#: a user's node whose thread blocks for good in its first timer callback, after saying so
STUCK = textwrap.dedent(
    """
    import threading

    import msgspec

    from turtlectl import Node


    class StuckParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
        speed: float = 0.5  # m/s: how fast it patrols


    class Stuck:
        Params = StuckParams

        def __init__(self, node: Node[StuckParams]):
            self.log = node.log
            node.timer(0.2, self.tick)

        def tick(self):
            self.log.info("blocking the node's thread")
            threading.Event().wait()
    """
)


def test_a_node_that_runs_but_does_not_answer_is_said_to_run_with_its_pid(tmp_path):
    """`param set patrol speed 1` on a node listed as running said "no node named 'patrol'
    answers (running: patrol)"; `log-level` asks it the same way (its parameters and details are
    answered off its thread: `param get` and `node info` still work)."""
    (tmp_path / "stuck.py").write_text(STUCK)
    (tmp_path / "launch.toml").write_text('[[node]]\nname = "patrol"\nrun = "./stuck.py:Stuck"\n')
    with running_system(tmp_path / "launch.toml", ready=("patrol",), cwd=tmp_path) as system:
        system.wait_line(r"patrol \| INFO blocking the node's thread", 30.0)
        pid = system.alive["patrol"]
        got = system.run_cli("param", "set", "patrol", "speed", "1")
        assert got.returncode == ExitCode.UNREACHABLE, got.stderr
        assert f"patrol runs (pid {pid}, host " in got.stderr, got.stderr
        assert "did not answer to set speed within 3 s: its thread is busy or blocked" in got.stderr, got.stderr
        assert "no node named" not in got.stderr
        assert system.run_cli("param", "get", "patrol", "speed").stdout.strip() == "0.5"
        got = system.run_cli("log-level", "patrol", "debug")
        assert got.returncode == ExitCode.UNREACHABLE, got.stderr
        assert f"patrol runs (pid {pid}, host " in got.stderr, got.stderr
