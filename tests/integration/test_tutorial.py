"""The getting-started tutorial works as written: every `turtlectl` command of its ```sh blocks
runs against a real system (tests/integration/harness.py), exits 0 and prints what the page says
it prints.  A command added to the tutorial fails this test until it has its expected phrase here."""

from __future__ import annotations

import os
import re
import shlex
import signal
import subprocess
import time

import pyte
import pytest

from tests.integration.harness import ROOT, pump, running_system, set_winsize, turtlectl, view_in_pty

pytestmark = pytest.mark.integration

TUTORIAL = ROOT / "docs" / "tutorials" / "getting-started.md"

#: each command of the tutorial, in its order, and a phrase its output must contain (a regular
#: expression where the figures vary: the turtle rests anywhere within the 1 cm tolerance)
EXPECTED = {
    "turtlectl list": "status_monitor",
    "turtlectl goto 8 5 90": re.compile(r"reached at \((7\.99|8\.0)"),
    "turtlectl echo robot/status --once": "# turtlectl/TurtleStatus",
    "turtlectl echo robot/status --field x --field y --count 3": re.compile(
        r"^(7\.99\d*|8(\.0\d*)?) (4\.99\d*|5(\.0\d*)?)$", re.M
    ),
    "turtlectl echo obstacles --once --json": '"type":"turtlectl/LaserScan"',
    "turtlectl hz robot/status --duration 2": "robot/status: ",
    "turtlectl param list navigator": "goal_timeout",
    "turtlectl param get navigator goal_timeout": "30",
    "turtlectl node info navigator": "kind navigator",
    "turtlectl interface show TurtleStatus": "battery",
    "turtlectl view": "battery",  # on a pseudo-terminal, quit with q
    "turtlectl teleport 2 2 45": "teleported to (2, 2, 45 deg)",
    "turtlectl reset": "turtle back at its spawn pose",
}

#: commands that talk to no system (no --connect option)
OFFLINE = ("interface",)


def _shows(expected: str | re.Pattern[str], output: str) -> bool:
    return expected.search(output) is not None if isinstance(expected, re.Pattern) else expected in output


def tutorial_commands(text: str) -> list[str]:
    """The `turtlectl` lines of the page's ```sh blocks, without their comments."""
    blocks = re.findall(r"```sh\n(.*?)```", text, re.DOTALL)
    return [
        line.split(" #", 1)[0].strip()
        for block in blocks
        for line in block.splitlines()
        if line.startswith("turtlectl ")
    ]


def test_every_command_of_the_tutorial_has_its_expected_output_here():
    assert tutorial_commands(TUTORIAL.read_text()) == list(EXPECTED)


def _view(endpoint: str) -> str:
    pid, fd = view_in_pty(endpoint)
    screen = pyte.Screen(100, 30)
    stream = pyte.ByteStream(screen)
    try:
        set_winsize(fd, 30, 100)
        os.kill(pid, signal.SIGWINCH)
        deadline = time.monotonic() + 15
        while not _shows(EXPECTED["turtlectl view"], "\n".join(screen.display)):
            assert time.monotonic() < deadline, "\n".join(screen.display)
            assert pump(fd, stream, 0.2)
        shown = "\n".join(screen.display)
        os.write(fd, b"q")
        end = time.monotonic() + 5
        while pump(fd, stream, 0.1) and time.monotonic() < end:
            pass
        _, status = os.waitpid(pid, 0)
        assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0, status
        return shown
    finally:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        os.close(fd)


def test_the_tutorial_runs_against_a_real_system():
    with running_system() as system:
        for command in tutorial_commands(TUTORIAL.read_text()):
            args = shlex.split(command)[1:]
            if args == ["view"]:
                output = _view(system.endpoint)
            elif args[0] in OFFLINE:
                done = subprocess.run([*turtlectl(), *args], capture_output=True, text=True, timeout=30)
                assert done.returncode == 0, (command, done.stdout, done.stderr)
                output = done.stdout
            else:
                done = system.run_cli(*args)
                assert done.returncode == 0, (command, done.stdout, done.stderr)
                output = done.stdout
            assert _shows(EXPECTED[command], output), (command, output)
