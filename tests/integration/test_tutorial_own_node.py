"""The tutorial "Write your own node" works as written, in a project folder of its own (a copy of
examples/patrol outside the repository): every command of its ```sh blocks runs there, exits 0 and
prints what the page says; `turtlectl launch` (a ```console block: it runs until Ctrl-C) is the
system the others talk to."""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.integration.harness import ROOT, running_system, turtlectl
from tests.integration.test_tutorial import tutorial_commands

pytestmark = pytest.mark.integration

TUTORIAL = ROOT / "docs" / "tutorials" / "your-own-node.md"

#: each command, in the page's order, and a phrase its output must contain
EXPECTED = {
    "turtlectl launch --check": "launch.toml: valid",
    "turtlectl list": "patrol ",
    "turtlectl node info patrol": "kind ./patrol.py:Patrol",
    "turtlectl param describe patrol side": "meaning:     the square's side",
    "turtlectl param set patrol laps 2": "patrol laps = 2 (was 1)",
    "turtlectl log --node patrol": "patrol: parameter laps: 1 -> 2",
    "pytest -q": " passed",
}


def test_every_command_of_the_tutorial_has_its_expected_output_here():
    commands = tutorial_commands(TUTORIAL.read_text()) + [
        line.strip() for line in TUTORIAL.read_text().splitlines() if line.strip() == "pytest -q"
    ]
    assert commands == list(EXPECTED)


def test_the_tutorial_runs_in_a_project_folder_of_its_own(tmp_path):
    project = tmp_path / "patrol"
    shutil.copytree(ROOT / "examples" / "patrol", project, ignore=shutil.ignore_patterns("__pycache__"))
    with running_system(project / "launch.toml", ready=("sim", "navigator", "patrol"), cwd=project) as system:
        env = {**os.environ, "TURTLECTL_CONNECT": system.endpoint}
        for command, expected in EXPECTED.items():
            args = shlex.split(command)
            # `pytest` as the page says: the console script (python -m pytest would put the folder on sys.path)
            pytest_script = str(Path(sys.executable).parent / "pytest")
            argv = (
                [pytest_script, *args[1:], "-p", "no:cacheprovider"]
                if args[0] == "pytest"
                else [*turtlectl(), *args[1:]]
            )
            done = subprocess.run(argv, cwd=project, env=env, capture_output=True, text=True, timeout=600, check=False)
            assert done.returncode == 0, (command, done.stdout, done.stderr)
            assert expected in done.stdout, (command, done.stdout)
        assert system.stop() == 0
