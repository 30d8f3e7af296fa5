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


#: the capstone's sections (8 and 9), run in a copy of examples/capstone beside its own system
CAPSTONE_EXPECTED = {
    "turtlectl goto 8.5 5.5 180": "reached at",
    "turtlectl echo robot/status --once": "# capstone_msgs/TurtleStatus",
    "turtlectl interface show capstone_msgs/TurtleStatus": "battery",
    "turtlectl interface show TurtleStatus": "capstone_msgs/TurtleStatus",
    "turtlectl action list": "navigate_to",
    "pytest -q": " passed",
    "turtlectl verify capstone.toml --launch launch.toml --short 10": "10 of 10 hold",
}

CAPSTONE_SECTIONS = "## 8. "


def page_parts() -> tuple[str, str]:
    """The page before the capstone's sections, and those sections."""
    text = TUTORIAL.read_text()
    at = text.index(CAPSTONE_SECTIONS)
    return text[:at], text[at:]


def commands_of(text: str) -> list[str]:
    """The turtlectl commands of ``text``'s ```sh blocks, and its ``pytest -q`` lines, in order."""
    lines = [line.split(" #", 1)[0].strip() for line in text.splitlines()]
    wanted = set(tutorial_commands(text)) | {"pytest -q"}
    return [line for line in lines if line in wanted]


def run_commands(project: Path, expected: dict[str, str], env: dict[str, str]) -> None:
    """Each command in ``project`` (``pytest`` as the page says: the console script, as python -m
    pytest would put the folder on sys.path): exit 0 and the phrase the page promises."""
    pytest_script = str(Path(sys.executable).parent / "pytest")
    for command, phrase in expected.items():
        args = shlex.split(command)
        argv = (
            [pytest_script, *args[1:], "-p", "no:cacheprovider"] if args[0] == "pytest" else [*turtlectl(), *args[1:]]
        )
        done = subprocess.run(argv, cwd=project, env=env, capture_output=True, text=True, timeout=600, check=False)
        assert done.returncode == 0, (command, done.stdout, done.stderr)
        assert phrase in done.stdout, (command, done.stdout)


def test_every_command_of_the_tutorial_has_its_expected_output_here():
    own_node, capstone = page_parts()
    assert sorted(commands_of(own_node)) == sorted(EXPECTED)
    assert commands_of(capstone) == list(CAPSTONE_EXPECTED)


def test_the_capstone_sections_run_in_a_project_folder_of_their_own(tmp_path):
    project = tmp_path / "capstone"
    shutil.copytree(ROOT / "examples" / "capstone", project, ignore=shutil.ignore_patterns("__pycache__"))
    ready = ("sim", "navigator", "obstacle_detector")  # status_monitor's status is the project's own type
    with running_system(project / "launch.toml", ready=ready, cwd=project) as system:
        run_commands(project, CAPSTONE_EXPECTED, {**os.environ, "TURTLECTL_CONNECT": system.endpoint})
        assert system.stop() == 0


def test_the_tutorial_runs_in_a_project_folder_of_its_own(tmp_path):
    project = tmp_path / "patrol"
    shutil.copytree(ROOT / "examples" / "patrol", project, ignore=shutil.ignore_patterns("__pycache__"))
    with running_system(project / "launch.toml", ready=("sim", "navigator", "patrol"), cwd=project) as system:
        run_commands(project, EXPECTED, {**os.environ, "TURTLECTL_CONNECT": system.endpoint})
        assert system.stop() == 0
