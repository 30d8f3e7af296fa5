"""`turtlectl plot` as a user runs it, without a system (issue 28): a recording into a PNG, an
SVG or the terminal; each mistake one line with exit code 2, nothing to plot exit code 3; and
`turtlectl --help` does not pay for plotext and matplotlib."""

from __future__ import annotations

import subprocess
import sys

import pytest
import typer
from typer.testing import CliRunner

from turtlectl.cli.errors import ExitCode, TurtlectlError, exit_code
from turtlectl.cli.main import app, error_line
from turtlectl.messages import Pose, TurtleStatus, encode, encoding_for

START = 1_700_000_000_000_000_000


def run(*argv: str) -> tuple[int, str]:
    """Exit code and what the user reads (an error of ours as cli.main prints it)."""
    result = CliRunner().invoke(app, ["plot", *argv])
    if isinstance(result.exception, TurtlectlError):
        return int(exit_code(result.exception)), error_line(result.exception)
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return result.exit_code, result.output


@pytest.fixture
def rec(tmp_path, monkeypatch):
    """run.mcap in the current folder: 2 s of poses and statuses."""
    from turtlectl.cli.commands import plotting
    from turtlectl.cli.recording.bag import BagWriter

    monkeypatch.setattr(plotting, "result", typer.echo)  # its SIG_IGN for Ctrl-C would outlive the test
    monkeypatch.chdir(tmp_path)
    writer = BagWriter(tmp_path / "run.mcap")
    for i in range(100):
        t = START + i * 20_000_000
        writer.add("turtle1/pose", encoding_for(Pose), encode(Pose(x=1 + i / 50, y=5, theta=0, seq=i)), t)
        if i % 5 == 0:
            status = TurtleStatus(x=0, y=0, theta=0, vel_x=0, vel_y=0, battery=100 - i / 20, seq=i)
            writer.add("robot/status", encoding_for(TurtleStatus), encode(status), t)
    writer.close()
    return tmp_path


def test_a_recording_into_a_png(rec):
    code, text = run("robot/status.battery", "turtle1/pose.x", "--input", "run.mcap", "--output", "out.png")
    assert (code, text) == (0, "wrote out.png: 120 samples of 2 series over 2.0 s\n")
    assert (rec / "out.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_recording_into_an_svg_names_each_series(rec):
    code, _ = run("robot/status.battery", "turtle1/pose.x", "-i", "run.mcap", "-o", "out.svg")
    svg = (rec / "out.svg").read_text()
    assert code == 0 and "robot/status.battery" in svg and "turtle1/pose.x" in svg and "run.mcap" in svg


def test_a_recording_in_the_terminal_is_one_chart(rec):
    code, text = run("turtle1/pose.x", "-i", "run.mcap")
    lines = text.splitlines()
    assert code == 0 and lines[0] == "━━ turtle1/pose.x" and "\x1b" not in text  # no colors into a pipe
    assert "time (s)" in lines[-2] and lines[-1] == "run.mcap: 100 samples over 2.0 s"


@pytest.mark.parametrize(
    "argv, said",
    [
        (("turtle1/pose.x", "-i", "run.mcap", "-o", "out.jpg"), "--output 'out.jpg': write a .png or .svg file"),
        (("turtle1/pose.z", "-i", "run.mcap"), "turtle1/pose.z: Pose has no field 'z'; the numeric fields of Pose: x,"),
        (("turtle1/pose", "-i", "run.mcap"), "'turtle1/pose': name a field after the key and a '.', as robot/status"),
        (("turtle1/pose.x", "-i", "run.mcap", "--duration", "3"), "--duration is for a running system"),
        (("turtle1/pose.x", "-i", "nothing.mcap"), "nothing.mcap: no such file"),
        (("turtle1/pose.x", "--window", "nan", "-o", "a.png"), "--window must be a finite number, got nan"),
        (
            ("turtle1/pose.x", "--connect", "tcp/127.0.0.1:9"),
            "the live plot draws in a terminal, and the output is not one",
        ),
    ],
)
def test_each_mistake_is_one_line_and_exit_code_2(rec, argv, said):
    code, text = run(*argv)
    assert code == ExitCode.BAD_INPUT and text.startswith(f"turtlectl: error: {said}"), text
    assert not (rec / "out.jpg").exists()


def test_a_key_the_recording_does_not_hold_is_exit_code_3(rec):
    code, text = run("obstacles.ranges.0", "-i", "run.mcap", "-o", "out.png")
    assert (code, text) == (
        ExitCode.UNREACHABLE,
        "turtlectl: error: run.mcap has no messages on obstacles (it holds robot/status, turtle1/pose)",
    )
    assert not (rec / "out.png").exists()


def test_no_router_for_a_live_picture_is_exit_code_3(tmp_path):
    code, text = run("turtle1/pose.x", "-o", str(tmp_path / "a.png"), "--duration", "1", "--connect", "tcp/127.0.0.1:9")
    assert code == ExitCode.UNREACHABLE and "no turtlectl system at tcp/127.0.0.1:9" in text


def test_help_does_not_import_the_plotting_libraries():
    """`turtlectl --help` stays quick: plotext and matplotlib load with `plot` only."""
    heavy = ["plotext", "matplotlib", "turtlectl.cli.tools.plot", "turtlectl.cli.tools.plot_draw"]
    code = f"import turtlectl.cli.main, sys; print([m for m in {heavy!r} if m in sys.modules])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
