"""`turtlectl plot` against the real system: a recording of it drawn into a PNG and an
SVG; the live plot in a pseudo-terminal, read back through a terminal emulator (pyte), ended by
q and by Ctrl-C; a picture of the live system after --duration; nothing to plot is exit code 3
with the reason.  No fixed sleeps: every wait is for the screen (or a file) under a deadline."""

from __future__ import annotations

import os
import re
import signal
import struct
import time

import pyte
import pytest

from tests.integration.harness import in_pty, pump, set_winsize
from turtlectl.runtime.client.errors import ExitCode

pytestmark = pytest.mark.integration

ROWS, COLS = 30, 100


def png_size(data: bytes) -> tuple[int, int]:
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR", data[:16]
    return struct.unpack(">II", data[16:24])


def test_a_recording_of_the_system_is_plotted_into_a_png_and_an_svg(system, tmp_path):
    rec = tmp_path / "rec.mcap"
    recorded = system.run_cli("record", "turtle1/pose", "robot/status", "-o", str(rec), "--duration", "1.5")
    assert recorded.returncode == 0, recorded.stderr
    png, svg = tmp_path / "out.png", tmp_path / "out.svg"
    result = system.run_cli("plot", "robot/status.battery", "turtle1/pose.x", "--input", str(rec), "--output", str(png))
    assert result.returncode == 0, result.stderr
    assert re.fullmatch(r"wrote \S+out\.png: \d+ samples of 2 series over 1\.\d s\n", result.stdout), result.stdout
    samples = int(result.stdout.split(": ")[1].split()[0])
    assert samples > 1.5 * (62.5 + 10) * 0.8  # poses at 62.5 Hz and statuses at 10 Hz, nearly all of them
    assert png_size(png.read_bytes()) == (1000, 500)
    result = system.run_cli("plot", "robot/status.battery", "turtle1/pose.x", "-i", str(rec), "-o", str(svg))
    assert result.returncode == 0, result.stderr
    text = svg.read_text()
    assert "<svg" in text and "robot/status.battery" in text and "turtle1/pose.x" in text and "time (s)" in text


class Terminal:
    """`turtlectl plot ARGS` in a pseudo-terminal of ROWS x COLS, its screen emulated by pyte."""

    def __init__(self, *args: str):
        self.pid, self.fd = in_pty("plot", *args)
        self.screen = pyte.Screen(COLS, ROWS)
        self.emulated = pyte.ByteStream(self.screen)
        self.written = bytearray()  # everything it wrote, as it wrote it
        set_winsize(self.fd, ROWS, COLS)
        os.kill(self.pid, signal.SIGWINCH)

    def feed(self, data: bytes) -> None:
        """What pump gives it: kept, and shown on the emulated screen."""
        self.written += data
        self.emulated.feed(data)

    @property
    def text(self) -> str:
        return "\n".join(self.screen.display)

    def wait_for(self, pattern: str, timeout: float = 15.0) -> re.Match[str]:
        deadline = time.monotonic() + timeout
        while (found := re.search(pattern, self.text)) is None:
            assert time.monotonic() < deadline, f"no {pattern!r} on the screen:\n{self.text}"
            assert pump(self.fd, self, 0.1), f"plot ended:\n{self.text}"
        return found

    def exit_code(self, timeout: float = 10.0) -> int:
        """Its exit code once it has ended (the terminal read to the end)."""
        deadline = time.monotonic() + timeout
        while pump(self.fd, self, 0.1):
            assert time.monotonic() < deadline, f"plot did not end:\n{self.text}"
        _, status = os.waitpid(self.pid, 0)
        return os.WEXITSTATUS(status) if os.WIFEXITED(status) else -os.WTERMSIG(status)

    def close(self) -> None:
        try:
            os.kill(self.pid, signal.SIGKILL)
            os.waitpid(self.pid, 0)
        except (ChildProcessError, ProcessLookupError):
            pass
        os.close(self.fd)


def test_a_live_plot_draws_each_series_with_its_axes_in_a_terminal_and_q_ends_it(system):
    system.teleport(3.0, 8.0, 0.0)  # x is 3 from now on
    term = Terminal("turtle1/pose.x", "robot/status.battery", "--window", "5", "--connect", system.endpoint)
    try:
        term.wait_for(r"turtle1/pose\.x 3  robot/status\.battery \d+(\.\d+)? \| q quits")
        display = term.screen.display
        assert display[0].split() == ["━━", "turtle1/pose.x", "━━", "robot/status.battery"]  # the legend
        assert "time (s)" in display[-2]  # the time axis, its label
        assert float(display[-3].split()[-1]) >= 5.0  # the time axis' ticks: the window's end last
        assert display[1].lstrip().startswith("┌") and "┤" in term.text  # the frame, the value axis' ticks
        assert any(c in term.text for c in "⠁⠂⠄⡀⢀⠈⠐⠠⣀⠉⠒⠤")  # the lines, in braille dots
        os.write(term.fd, b"q")
        assert term.exit_code() == ExitCode.OK
    finally:
        term.close()


def test_ctrl_c_ends_a_live_plot_with_exit_code_0_and_the_terminal_as_it_was(system):
    term = Terminal("robot/status.battery", "--connect", system.endpoint)
    try:
        term.wait_for(r"robot/status\.battery \d+(\.\d+)? \| q quits")
        os.write(term.fd, b"\x03")  # the terminal sends SIGINT
        assert term.exit_code() == ExitCode.OK
        assert pyte.modes.DECTCEM in term.screen.mode  # the cursor shown again
    finally:
        term.close()


def test_a_live_plot_with_a_duration_ends_by_itself_and_leaves_its_last_frame(system):
    term = Terminal("robot/status.battery", "--duration", "1", "--connect", system.endpoint)
    try:
        assert term.exit_code() == ExitCode.OK
        after = term.written.split(b"\x1b[?1049l")[-1].decode()  # once the alternate screen is left
        assert "robot/status.battery" in after and "time (s)" in after and "q quits" not in after
    finally:
        term.close()


def test_a_picture_of_the_live_system_after_its_duration(system, tmp_path):
    png = tmp_path / "live.png"
    result = system.run_cli("plot", "turtle1/pose.theta", "robot/status.battery", "-o", str(png), "--duration", "1")
    assert result.returncode == 0, result.stderr
    assert re.fullmatch(r"wrote \S+live\.png: \d+ samples of 2 series over 1\.\d s\n", result.stdout)
    assert "plotting turtle1/pose.theta, robot/status.battery into" in result.stderr
    assert png_size(png.read_bytes()) == (1000, 500)


def test_nothing_to_plot_is_exit_code_3_with_the_reason(system, tmp_path):
    png = tmp_path / "none.png"
    result = system.run_cli("plot", "navigate_to/feedback.eta", "-o", str(png), "--duration", "0.5")
    assert result.returncode == ExitCode.UNREACHABLE, result.stderr
    assert result.stderr.splitlines()[-1] == (
        "turtlectl: error: no message within 0.5 s: nothing published on navigate_to/feedback yet: navigator "
        "publishes it only while a goal runs (start one with `turtlectl goto X Y THETA`)"
    )
    assert not png.exists()


def test_a_field_that_is_no_number_is_exit_code_2_before_anything_is_drawn(system):
    result = system.run_cli("plot", "navigate_to/feedback.state", "--duration", "5")  # no terminal: said second
    assert result.returncode == ExitCode.BAD_INPUT
    assert result.stderr.startswith(
        "turtlectl: error: navigate_to/feedback.state: state is not a number; the numeric fields of "
        "turtlectl/NavigateToFeedback: distance_remaining, heading_remaining, eta,"
    )
