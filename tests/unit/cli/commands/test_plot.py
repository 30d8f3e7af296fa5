"""`turtlectl plot` as a user runs it, without a system: a recording into a PNG, an
SVG or the terminal; each mistake one line with exit code 2, nothing to plot exit code 3; and
`turtlectl --help` does not pay for plotext and matplotlib."""

from __future__ import annotations

import subprocess
import sys

import pytest
import typer
from typer.testing import CliRunner

from turtlectl.cli.main import app, error_line
from turtlectl.messages import Pose, TurtleStatus, encode, encoding_for
from turtlectl.runtime.client.errors import ExitCode, TurtlectlError, Unreachable, exit_code

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
        (
            ("turtle1/pose.z", "-i", "run.mcap"),
            "turtle1/pose.z: turtlectl/Pose has no field 'z'; the numeric fields of turtlectl/Pose: x,",
        ),
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


# -- what a new user meets -----------------------------------------------------------------------


def test_one_sample_is_said_in_the_singular():
    from pathlib import Path

    from turtlectl.cli.commands import plotting
    from turtlectl.cli.tools.plot import Series
    from turtlectl.cli.tools.plot_window import Collected

    x = Series("turtle1/pose", "x")
    collected = Collected([x])
    collected.add(x, 0.0, 1.0)
    assert plotting.wrote(Path("a.png"), collected, 2.0) == "wrote a.png: 1 sample of 1 series over 2.0 s"


def test_an_output_folder_that_does_not_exist_is_bad_input_before_anything_is_collected(tmp_path):
    code, text = run(
        "turtle1/pose.x", "-o", str(tmp_path / "no" / "a.png"), "--duration", "2", "--connect", "tcp/127.0.0.1:9"
    )
    assert (code, text) == (
        ExitCode.BAD_INPUT,
        f"turtlectl: error: --output {str(tmp_path / 'no' / 'a.png')!r}: no folder {tmp_path / 'no'}",
    )


def test_an_output_folder_that_is_a_file_is_bad_input(tmp_path):
    (tmp_path / "notes").write_text("")
    code, text = run("turtle1/pose.x", "-o", str(tmp_path / "notes" / "a.png"), "--connect", "tcp/127.0.0.1:9")
    assert code == ExitCode.BAD_INPUT and text.endswith(f"{tmp_path / 'notes'} is not a folder"), text


def test_a_recording_with_stamps_plots_on_them(rec):
    from turtlectl.cli.recording.bag import BagWriter

    writer = BagWriter(rec / "sim.mcap")
    for i in range(24):  # logged 0.1 s apart, stamped 0.5 s apart: simulated time at 5 x
        pose = encode(Pose(x=i, y=0, theta=0, stamp=START + i * 500_000_000))
        writer.add("turtle1/pose", encoding_for(Pose), pose, START + i * 100_000_000)
    writer.close()
    assert run("turtle1/pose.x", "-i", "sim.mcap", "-o", "out.png") == (
        0,
        "wrote out.png: 24 samples of 1 series over 2.3 s\n",
    )
    code, text = run("turtle1/pose.x", "-i", "sim.mcap", "-o", "out.png", "--stamps")
    assert (code, text) == (0, "wrote out.png: 24 samples of 1 series over 11.5 s\n")
    code, text = run("turtle1/pose.x", "-i", "run.mcap", "--stamps")  # none stamped
    assert code == ExitCode.UNREACHABLE and "not stamped" in text, text


class FakeLive:
    """plot_sources.Live with nothing to say but what a test gives it, its time past --duration."""

    def __init__(self, samples, silent):
        self.samples, self.silent, self.router, self.received = samples, silent, "", len(samples)
        self.typos = {}
        self.said = []

    def poll(self, wait=0.0):
        samples, self.samples = self.samples, []
        return samples

    def elapsed(self):
        return 5.0

    def now(self):
        return 5.0

    def why_silent(self):
        return "; ".join(self.silent.values())

    def close(self):
        pass


class FakeScreen:
    def size(self):
        return 100, 30

    def show(self, lines):
        pass

    def key(self, wait):
        return ""


def live_plot(monkeypatch, capsys, samples, silent):
    import contextlib

    from turtlectl.cli.commands import plotting
    from turtlectl.cli.tools import plot_draw, plot_sources
    from turtlectl.cli.tools.plot import Series
    from turtlectl.runtime.client import session as client

    series = [Series("turtle1/pose", "x"), Series("nobody/here", "x")]
    monkeypatch.setattr(plotting, "result", typer.echo)
    monkeypatch.setattr(client, "client_session", lambda connect, domain: contextlib.nullcontext())
    monkeypatch.setattr(plot_sources, "Live", lambda *a, **k: FakeLive([(series[0], t, 3.0) for t in samples], silent))
    monkeypatch.setattr(plot_draw, "screen", lambda out: contextlib.nullcontext(FakeScreen()))
    try:
        plotting.plot_live(series, 10.0, 1.0, "tcp/x:1", "", stamps=False)
    except TurtlectlError as error:
        return capsys.readouterr().out, error
    return capsys.readouterr().out, None


SILENT = {
    "nobody/here": "nothing published on nobody/here yet: no running node publishes it (`turtlectl list` shows the topics)"
}


def test_the_last_frame_of_a_duration_keeps_its_bottom_line(monkeypatch, capsys):
    out, error = live_plot(monkeypatch, capsys, [0.5, 1.0], SILENT)
    assert error is None and "time (s)" in out
    assert out.endswith("turtle1/pose.x 3  nobody/here.x (silent: no running node publishes it)\n"), out[-200:]


def test_nothing_within_a_duration_ends_the_last_frame_with_a_newline_before_the_error(monkeypatch, capsys):
    out, error = live_plot(monkeypatch, capsys, [], SILENT)
    assert isinstance(error, Unreachable)
    assert out.endswith("nobody/here.x (silent: no running node publishes it)\n"), out[-200:]


def test_the_screen_ends_its_last_line_before_leaving():
    import io

    from turtlectl.cli.tools import plot_draw

    out = io.StringIO()
    with plot_draw.screen(out) as shown:
        shown.show(["a", "bottom line"])
    assert out.getvalue().endswith("bottom line\x1b[K\x1b[J\r\n\x1b[?25h\x1b[?1049l")


@pytest.mark.parametrize("first", ["run.mcap", "elsewhere.mcap"])
def test_a_recording_given_as_the_first_argument_says_to_use_input(rec, first):
    """`plot run.mcap robot/status.battery` read the file as a key (run, field mcap) and said
    there was no turtlectl system."""
    code, text = run(first, "robot/status.battery")
    assert (code, text) == (
        ExitCode.BAD_INPUT,
        f"turtlectl: error: {first} is a recording, not KEY.FIELD: plot it with --input, "
        f"as turtlectl plot robot/status.battery --input {first}",
    )


def test_an_existing_file_given_as_a_series_says_to_use_input(rec):
    (rec / "run.bag").write_bytes(b"")
    code, text = run("run.bag")
    assert code == ExitCode.BAD_INPUT
    assert text == (
        "turtlectl: error: run.bag is a file, not KEY.FIELD: plot a recording with --input, "
        "as turtlectl plot robot/status.battery --input run.bag"
    )
