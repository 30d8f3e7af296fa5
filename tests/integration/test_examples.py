"""The example project (examples/patrol) passes its own tests from a folder of
its own, through turtlectl's pytest plugin and FakeNode; and the plugin fails a test at once,
with the node's traceback, when a node dies while the system starts, leaving no process behind."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import psutil
import pytest

pytestmark = pytest.mark.integration

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "patrol"


def pytest_in(folder: Path, *options: str) -> subprocess.CompletedProcess[str]:
    """The project's own ``pytest`` (the console script, as a user runs it), in its folder."""
    return subprocess.run(
        [str(Path(sys.executable).parent / "pytest"), "-q", "-p", "no:cacheprovider", *options],
        cwd=folder,
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )


def left_in(folder: Path) -> list[str]:
    """Processes still running in ``folder`` (a launch or a node of it)."""
    found = []
    for proc in psutil.process_iter(["cwd", "cmdline"]):
        try:
            if proc.info["cwd"] == str(folder):
                found.append(" ".join(proc.info["cmdline"] or []))
        except psutil.Error:
            continue
    return found


def test_the_example_project_passes_its_own_tests(tmp_path):
    project = tmp_path / "patrol"
    shutil.copytree(EXAMPLE, project, ignore=shutil.ignore_patterns("__pycache__"))
    done = pytest_in(project)
    assert done.returncode == 0, done.stdout + done.stderr
    assert " passed" in done.stdout and "failed" not in done.stdout
    assert left_in(project) == []


def test_a_node_dying_while_the_system_starts_fails_the_test_with_its_traceback(tmp_path):
    (tmp_path / "broken.py").write_text(
        textwrap.dedent(
            """
            import msgspec


            class Broken:
                Params = msgspec.defstruct("BrokenParams", [])

                def __init__(self, node):
                    raise RuntimeError("the broken node cannot start")
            """
        )
    )
    (tmp_path / "launch.toml").write_text(
        '[[node]]\nname = "sim"\nrun = "sim"\n\n[[node]]\nname = "broken"\nrun = "./broken.py:Broken"\n'
    )
    (tmp_path / "test_it.py").write_text("def test_never_runs(turtlectl_system):\n    raise AssertionError('ran')\n")
    done = pytest_in(tmp_path)
    assert done.returncode == 1, done.stdout + done.stderr
    assert "broken exited with code 1 while the system started" in done.stdout, done.stdout
    assert "RuntimeError: the broken node cannot start" in done.stdout and "'ran'" not in done.stdout
    assert left_in(tmp_path) == []


def test_a_projects_tests_run_in_simulated_time_with_the_plugins_option(tmp_path):
    """``pytest --turtlectl-time-scale 5`` starts turtlectl_system's system with
    ``launch --time-scale 5``: the simulator's clock says 5, a goal's time is simulated seconds."""
    (tmp_path / "launch.toml").write_text(
        '[[node]]\nname = "sim"\nrun = "sim"\n\n[[node]]\nname = "navigator"\nrun = "navigator"\n'
    )
    (tmp_path / "test_fast.py").write_text(
        textwrap.dedent(
            """
            import time


            def test_fast(turtlectl_system):
                assert turtlectl_system.latest("clock").real_time_factor == 5.0
                started = time.monotonic()
                response = turtlectl_system.goto(8.5, 5.5, 180.0)
                assert response.success and response.time_taken > time.monotonic() - started
            """
        )
    )
    done = pytest_in(tmp_path, "--turtlectl-time-scale", "5")
    assert done.returncode == 0, done.stdout + done.stderr
    assert left_in(tmp_path) == []


def record_sim_pid(name: str) -> str:
    """A test of a project that notes which system it ran on (the sim's pid) in pids.txt."""
    return textwrap.dedent(
        f"""
        def test_{name}(turtlectl_system):
            pid = next(n.pid for n in turtlectl_system.nodes() if n.name == "sim")
            with open("pids.txt", "a") as f:
                f.write(f"{{__name__}}.{name} {{pid}}\\n")
        """
    )


def test_a_module_shares_one_system_per_launch_file_with_the_scope_option(tmp_path):
    """``turtlectl_scope = module``: the tests of a module asking for the same launch file and
    options share one system; another marker (on a test or a module) gets its own, and so does
    ``fresh=True``; the next module starts again."""
    sim = '[[node]]\nname = "sim"\nrun = "sim"\n'
    (tmp_path / "launch.toml").write_text(sim)
    (tmp_path / "other.toml").write_text(sim)
    (tmp_path / "pytest.ini").write_text("[pytest]\nturtlectl_scope = module\n")
    one = "import pytest\n" + record_sim_pid("a") + record_sim_pid("b")
    one += '\n@pytest.mark.turtlectl_launch("other.toml")' + record_sim_pid("c")
    one += '\n@pytest.mark.turtlectl_launch("launch.toml", fresh=True)' + record_sim_pid("d")
    (tmp_path / "test_one.py").write_text(one)
    two = 'import pytest\n\npytestmark = pytest.mark.turtlectl_launch("other.toml")\n'
    (tmp_path / "test_two.py").write_text(two + record_sim_pid("a") + record_sim_pid("b"))
    done = pytest_in(tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    pid = dict(line.split() for line in (tmp_path / "pids.txt").read_text().splitlines())
    assert pid["test_one.a"] == pid["test_one.b"]
    assert pid["test_two.a"] == pid["test_two.b"]
    assert len({pid["test_one.a"], pid["test_one.c"], pid["test_one.d"], pid["test_two.a"]}) == 4
    assert left_in(tmp_path) == []
    wrong = pytest_in(tmp_path, "--turtlectl-scope", "forever")
    assert wrong.returncode == 4 and "turtlectl_scope must be one of" in wrong.stderr, wrong.stdout + wrong.stderr


def test_a_node_dying_while_a_shared_system_runs_fails_the_test_it_died_in_with_its_output(tmp_path):
    (tmp_path / "boom.py").write_text(
        textwrap.dedent(
            """
            import msgspec

            from turtlectl.messages import Twist


            class Boom:
                Params = msgspec.defstruct("BoomParams", [])

                def __init__(self, node):
                    node.subscribe("boom", Twist, self.on_boom)

                def on_boom(self, message):
                    raise RuntimeError("boom on request")
            """
        )
    )
    (tmp_path / "launch.toml").write_text(
        '[[node]]\nname = "sim"\nrun = "sim"\n\n[[node]]\nname = "boom"\nrun = "./boom.py:Boom"\n'
        "respawn = true\nrespawn_delay = 0.1\n"
    )
    (tmp_path / "test_it.py").write_text(
        textwrap.dedent(
            """
            import time

            from turtlectl.messages import Twist


            def names(client):
                return {n.name for n in client.nodes()}


            def test_boom(turtlectl_system):
                deadline, seen = time.monotonic() + 30.0, False
                while True:  # until boom is gone from the graph, once seen there
                    here = "boom" in names(turtlectl_system)
                    if seen and not here:
                        break
                    seen = seen or here
                    assert time.monotonic() < deadline, "boom never exited"
                    turtlectl_system.publish("boom", Twist())


            def test_respawned(turtlectl_system):
                deadline = time.monotonic() + 30.0
                while "boom" not in names(turtlectl_system):  # its exit was told before its respawn
                    assert time.monotonic() < deadline, "boom never came back"


            def test_later(turtlectl_system):
                assert {"sim", "boom"} <= names(turtlectl_system)
            """
        )
    )
    done = pytest_in(tmp_path, "--turtlectl-scope", "session", "-rA")
    assert done.returncode == 1, done.stdout + done.stderr
    # its exit is told once the supervisor has reaped it, a moment after its token went: in
    # the teardown of test_boom or test_respawned, or before test_respawned (which then does not run)
    said = re.search(r"boom exited with code 1 (during test_boom|between the tests|during test_respawned)", done.stdout)
    assert said, done.stdout
    assert "RuntimeError: boom on request" in done.stdout
    assert done.stdout.count("Failed: boom exited with code 1") == 1  # once: the respawned boom serves on
    assert "PASSED test_it.py::test_later" in done.stdout
    assert left_in(tmp_path) == []
