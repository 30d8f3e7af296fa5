"""Issue 24 (5, 6): the example project (examples/patrol) passes its own tests from a folder of
its own, through turtlectl's pytest plugin and FakeNode; and the plugin fails a test at once,
with the node's traceback, when a node dies while the system starts, leaving no process behind."""

from __future__ import annotations

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
    """Issue 28: ``pytest --turtlectl-time-scale 5`` starts turtlectl_system's system with
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
