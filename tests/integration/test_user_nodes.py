"""A launch file runs a user's own node class beside the built-ins, from a
project in its own folder: ready, its parameters served, respawned after a kill -9, run in
the foreground by ``turtlectl run ./patrol.py:Patrol``; a ``run`` that names no node class
is one line and exit 2 with nothing started."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import textwrap
from pathlib import Path

import pytest

from tests.integration.harness import running_system, turtlectl
from turtlectl.runtime.client.errors import ExitCode

pytestmark = pytest.mark.integration

PATROL = textwrap.dedent(
    '''
    """A user's node, in a project folder of its own."""

    from typing import Annotated

    import msgspec

    from messages import Waypoint  # the project's own messages.py: never turtlectl's

    from turtlectl import Interface, Node, run_main
    from turtlectl.messages import Twist


    class PatrolParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
        side: Annotated[float, msgspec.Meta(gt=0.0, le=10.0)] = 2.0  # m: the square's side
        laps: int = 3  # -: laps before it rests


    class Patrol:
        Params = PatrolParams

        def __init__(self, node: Node[PatrolParams]):
            corner = Waypoint(x=node.params.side)
            node.log.info("patrolling a %g m square", corner.x)


    class Mover:
        """Drives the turtle forward: what an undeclared user kind may do under --secure."""

        Params = PatrolParams

        def __init__(self, node: Node[PatrolParams]):
            pub = node.publisher("turtle1/cmd_vel", Twist)
            node.timer(0.1, lambda: pub.publish(Twist(linear=0.5, angular=0.0)))


    class Alarm:
        """Declares an Interface, then publishes outside it."""

        Params = PatrolParams
        Interface = Interface(publishes=("alarm/state",))

        def __init__(self, node):
            node.publisher("alarm/state", Twist)
            node.publisher("robot/alarm", Twist)


    class Broken:
        Params = PatrolParams

        def __init__(self, node):
            raise RuntimeError("the patrol cannot start")


    if __name__ == "__main__":
        run_main(Patrol, PatrolParams)
    '''
)

LAUNCH = textwrap.dedent(
    """
    [[node]]
    name = "sim"
    run = "sim"

    [[node]]
    name = "guard"
    run = "./patrol.py:Patrol"
    params = { side = 3.5 }
    respawn = true
    respawn_delay = 0.2

    [[node]]
    name = "broken"
    run = "./patrol.py:Broken"
    """
)


#: a project's own modules named as turtlectl's packages: they shadow nothing of turtlectl's
SHADOWS = {
    "messages.py": "import msgspec\n\n\nclass Waypoint(msgspec.Struct):\n    x: float\n",
    "runtime.py": "raise ImportError('the project runtime.py was imported by turtlectl')\n",
    "nodes/__init__.py": "raise ImportError('the project nodes/ was imported by turtlectl')\n",
    "cli.py": "raise ImportError('the project cli.py was imported by turtlectl')\n",
    "sim.py": "raise ImportError('the project sim.py was imported by turtlectl')\n",
}


@pytest.fixture
def project(tmp_path: Path) -> Path:
    for name, text in SHADOWS.items():
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_text(text)
    (tmp_path / "patrol.py").write_text(PATROL)
    (tmp_path / "launch.toml").write_text(LAUNCH)
    return tmp_path


def test_a_user_node_class_runs_beside_the_builtins_supervised_as_they_are(project):
    with running_system(project / "launch.toml", ready=("sim", "guard"), cwd=project) as system:
        got = system.run_cli("param", "get", "guard", "side")
        assert got.returncode == 0 and json.loads(got.stdout) == 3.5, got.stderr
        described = json.loads(system.run_cli("param", "describe", "guard", "side", "--json").stdout)
        assert (described["unit"], described["meaning"]) == ("m", "the square's side")

        # a node that raises while starting: one traceback, its exit reported, not respawned (respawn = false)
        system.wait_line(r"broken exited with code 1", 30.0)
        assert system.output().count("Traceback") == 1 and "RuntimeError: the patrol cannot start" in system.output()

        old = system.alive["guard"]
        os.kill(old, signal.SIGKILL)
        system.wait_until(lambda: system.alive.get("guard", old) != old, 30.0, "guard respawned")
        assert "guard was killed by SIGKILL; respawning in 0.2 s (respawn 1)" in system.output()

        # `turtlectl run ./patrol.py:Patrol` in the foreground, named after its class, joining the system
        run = subprocess.Popen(
            [
                *turtlectl(),
                "run",
                "./patrol.py:Patrol",
                "-p",
                "side=1.5",
                "--name",
                "scout",
                "--connect",
                system.endpoint,
            ],
            cwd=project,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            text=True,
        )
        try:
            system.wait_until(lambda: "scout" in system.alive or run.poll() is not None, 30.0, "turtlectl run")
            assert run.poll() is None, run.communicate()[0]
            assert json.loads(system.run_cli("param", "get", "scout", "side").stdout) == 1.5
            run.send_signal(signal.SIGINT)
            out, _ = run.communicate(timeout=10)
            assert run.returncode == 0, out
            assert "patrolling a 1.5 m square" in out
            assert "running ./patrol.py:Patrol as node scout" in out
        finally:
            if run.poll() is None:
                run.kill()
                run.wait()
        assert system.stop() == 1  # `broken` never started: the system was incomplete


def test_under_secure_an_undeclared_user_kind_joins_and_drives_as_a_teleop_client_may(project, monkeypatch):
    tmp_path = project
    (tmp_path / "launch.toml").write_text(
        '[[node]]\nname = "sim"\nrun = "sim"\n\n[[node]]\nname = "mover"\nrun = "./patrol.py:Mover"\n'
    )
    monkeypatch.setenv("TURTLECTL_CREDENTIALS", str(tmp_path / "credentials.json"))  # never the user's own
    with running_system(
        tmp_path / "launch.toml", ready=("sim", "mover"), extra_args=("--secure",), cwd=project
    ) as system:
        system.wait_moving(0.4, timeout=20.0)  # its cmd_vel got through the router's rules
        got = system.run_cli("param", "get", "mover", "side")
        assert got.returncode == 0 and json.loads(got.stdout) == 2.0, got.stderr


BAD = [
    ("./nowhere.py:Patrol", "node[0] (guard).run: no file ./nowhere.py (looked for "),
    ("./patrol.py:Patrl", "node[0] (guard).run: patrol.py has no Patrl; did you mean Patrol?"),
    ("./patrol.py:PatrolParams", "node[0] (guard).run: patrol.py:PatrolParams is not a node class: it has no Params"),
    ("./syntax.py:Patrol", "node[0] (guard).run: cannot import ./syntax.py: SyntaxError: "),
    ("./importing.py:Patrol", "node[0] (guard).run: cannot import ./importing.py: ModuleNotFoundError: "),
]


@pytest.mark.parametrize(("run", "error"), BAD)
def test_a_run_that_names_no_node_class_is_one_line_and_exit_2(project, run, error):
    tmp_path = project
    (tmp_path / "syntax.py").write_text("class Patrol(:\n    pass\n")
    (tmp_path / "importing.py").write_text("import os\nimport no_such_package_of_yours\n")
    (tmp_path / "launch.toml").write_text(f'[[node]]\nname = "guard"\nrun = "{run}"\n')
    done = subprocess.run(
        [*turtlectl(), "launch", "launch.toml", "--check"], cwd=tmp_path, capture_output=True, text=True, timeout=60
    )
    assert done.returncode == ExitCode.BAD_INPUT and done.stdout == "", done.stdout
    assert done.stderr.splitlines() == [done.stderr.strip()] and error in done.stderr, done.stderr
    if run.startswith("./syntax"):
        assert "(syntax.py, line 1)" in done.stderr
    if run.startswith("./importing"):
        assert "no_such_package_of_yours' (importing.py, line 2)" in done.stderr


def test_params_of_a_user_node_that_do_not_validate_start_nothing(project):
    done = subprocess.run(
        [*turtlectl(), "launch", "launch.toml", "--set", "guard.sidee=1"],
        cwd=project,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == ExitCode.BAD_INPUT, done.stdout + done.stderr
    assert done.stderr.strip() == "turtlectl: error: --set guard.sidee: unknown key; did you mean side?"
    assert "starting" not in done.stdout
    run = subprocess.run(
        [*turtlectl(), "run", "./patrol.py:Patrol", "-p", "side=-1"], cwd=project, capture_output=True, text=True
    )
    assert run.returncode == ExitCode.BAD_INPUT and run.stderr.splitlines() == [
        "turtlectl: error: --param patrol.side must be > 0 (got -1)"
    ], run.stderr


def test_a_declaration_outside_its_interface_stops_the_node_with_exit_2_not_respawned(project):
    """What --secure's router would drop silently is refused by the runtime at once,
    in every mode: one line naming the key and where, exit 2, and respawn cannot help."""
    (project / "launch.toml").write_text(
        '[[node]]\nname = "sim"\nrun = "sim"\n\n[[node]]\nname = "alarm"\nrun = "./patrol.py:Alarm"\n'
        "respawn = true\nrespawn_delay = 0.1\n"
    )
    with running_system(project / "launch.toml", ready=("sim",), cwd=project) as system:
        system.wait_line(r"alarm exited with code 2", 30.0)
        out = system.output()
        assert "alarm may not publish robot/alarm: its Interface publishes alarm/state" in out, out
        assert "patrol.py:" in out and "Traceback" not in out
        assert "respawning cannot help" in out and "respawning in" not in out


HELLO = """import msgspec


class Hello:
    Params = msgspec.defstruct("HelloParams", [("greeting", str, "hi")])

    def __init__(self, node):
        import os

        node.log.info("%s from %s", node.params.greeting, os.getcwd())
"""


def test_a_module_class_is_found_in_the_launch_files_folder_from_anywhere(tmp_path):
    """``nodes.hello:Hello`` (the project's own ``nodes/`` package) is found in the launch file's
    folder first (`run`: the current folder), whatever folder `launch` runs from and whatever the
    order of the nodes, and user nodes and programs run in the launch file's folder."""
    project = tmp_path / "proj"
    (project / "nodes").mkdir(parents=True)
    (project / "nodes" / "__init__.py").write_text("")
    (project / "nodes" / "hello.py").write_text(HELLO)
    (project / "launch.toml").write_text(
        '[[node]]\nname = "sim"\nrun = "sim"\n\n[[node]]\nname = "hello"\nrun = "nodes.hello:Hello"\n'
    )
    checked = subprocess.run(
        [*turtlectl(), "launch", "proj/launch.toml", "--check"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert checked.returncode == 0, checked.stderr
    with running_system(project / "launch.toml", ready=("sim", "hello"), cwd=tmp_path) as system:
        system.wait_line(rf"hi from {project}$", 30.0)
    # `run` finds it in the current folder: imported, then its params checked (a number for a str: exit 2)
    ran = subprocess.run(
        [*turtlectl(), "run", "nodes.hello:Hello", "-p", "greeting=3"],
        cwd=project,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert ran.returncode == 2 and "--param hello.greeting must be text" in ran.stderr, ran.stderr
