"""Keyboard teleop against the real system, through a pseudo-terminal."""

from __future__ import annotations

import os
import signal
import subprocess
import termios
import time

import pytest

from tests.integration.harness import in_pty, pump, set_winsize, turtlectl
from turtlectl.messages import Twist, decode
from turtlectl.messages.keys import CMD_VEL
from turtlectl.runtime.client.errors import ExitCode

pytestmark = pytest.mark.integration


class Screen:
    """What a program in a pseudo-terminal wrote (raw text is enough for a status line)."""

    def __init__(self):
        self.text = ""

    def feed(self, data: bytes) -> None:
        self.text += data.decode("utf-8", "replace")


def teleop(system, *extra: str) -> tuple[int, int, Screen]:
    pid, fd = in_pty("teleop", "--connect", system.endpoint, *extra)
    set_winsize(fd, 30, 200)  # wide enough for the status line's note
    screen = Screen()
    deadline = time.monotonic() + 15
    while "| x " not in screen.text:  # the status line shows a pose: it is subscribed and drawing
        assert time.monotonic() < deadline, screen.text
        assert pump(fd, screen, 0.1), screen.text
    return pid, fd, screen


def hold(fd: int, screen: Screen, key: bytes, seconds: float) -> None:
    """A held key: the terminal repeats it every 40 ms."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        os.write(fd, key)
        pump(fd, screen, 0.04)


def ended(proc: subprocess.Popen, fd: int, screen: Screen, timeout: float = 10.0) -> tuple[str, str]:
    """Wait for ``proc`` to end while reading the terminal (unread, its buffer fills and teleop,
    blocked writing its status line, would read no key)."""
    deadline = time.monotonic() + timeout
    while proc.poll() is None:
        assert time.monotonic() < deadline, f"{proc.args} did not end within {timeout} s"
        pump(fd, screen, 0.05)
    return proc.communicate()


def finish(pid: int, fd: int, screen: Screen) -> int:
    while pump(fd, screen, 0.1):
        pass
    _, status = os.waitpid(pid, 0)
    return os.WEXITSTATUS(status) if os.WIFEXITED(status) else -1


def test_teleop_keys_move_the_turtle_the_right_way_space_stops_q_restores_the_terminal(system):
    system.teleport(3.0, 5.5, 0.0)
    pid, fd, screen = teleop(system, "--linear", "1.0")
    try:
        assert not termios.tcgetattr(fd)[3] & termios.ECHO  # cbreak: keys are read, not echoed
        hold(fd, screen, b"\x1b[A", 0.6)  # up: forward along the heading (+x)
        moving = system.wait_moving(0.5)
        assert moving.x > 3.1 and abs(moving.y - 5.5) < 1e-6 and "sending linear +1.00 m/s" in screen.text
        os.write(fd, b" ")
        stopped = system.wait_stopped(timeout=0.9)  # before the simulator's own 1 s command timeout
        hold(fd, screen, b"a", 0.6)  # a (left): counter-clockwise
        turned = system.latest_pose()
        assert 0.0 < turned.theta < 3.0 and abs(turned.x - stopped.x) < 1e-6, turned
        os.write(fd, b"q")
        assert finish(pid, fd, screen) == 0
        lflag = termios.tcgetattr(fd)[3]
        assert lflag & termios.ECHO and lflag & termios.ICANON  # the terminal as it was
    finally:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        os.close(fd)


def test_teleop_cancels_a_running_goal_and_leaves_on_sigterm_with_a_stop_sent(system):
    system.teleport(2.0, 3.0, 0.0)
    commands: list[bytes] = []
    sub = system.session.declare_subscriber(CMD_VEL, lambda s: commands.append(s.payload.to_bytes()))
    pid, fd, screen = teleop(system)
    try:
        goal = subprocess.Popen(
            [*turtlectl(), "goto", "9", "3", "0", "--connect", system.endpoint],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            stdin=subprocess.DEVNULL,
            text=True,
        )
        try:
            system.wait_moving(0.5)
            hold(fd, screen, b"\x1b[D", 0.3)  # the keys take over
            out, err = ended(goal, fd, screen)
        finally:
            goal.kill()
        assert goal.returncode == ExitCode.FAILED and "teleop" in out + err, (out, err)
        assert "canceled the running goal (reason teleop)" in screen.text
        deadline = time.monotonic() + 5  # the keys released: teleop stops sending (a goal now would be canceled)
        while not screen.text.rsplit("\x1b[K", 1)[-1].startswith("stopped"):
            assert time.monotonic() < deadline, screen.text[-300:]
            assert pump(fd, screen, 0.1)
        goal = subprocess.Popen(  # a goal started while the keys rest: space stops it too
            [*turtlectl(), "goto", "2", "8", "0", "--connect", system.endpoint],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            stdin=subprocess.DEVNULL,
            text=True,
        )
        try:
            system.wait_moving(0.5)
            os.write(fd, b" ")
            out, err = ended(goal, fd, screen)
        finally:
            goal.kill()
        assert goal.returncode == ExitCode.FAILED and "teleop" in out + err, (out, err)
        hold(fd, screen, b"\x1b[D", 0.3)
        os.kill(pid, signal.SIGTERM)
        assert finish(pid, fd, screen) == 0
        lflag = termios.tcgetattr(fd)[3]
        assert lflag & termios.ECHO and lflag & termios.ICANON

        def stopped() -> bool:
            last = decode(commands[-1], Twist) if commands else None
            return last is not None and (last.linear, last.angular) == (0.0, 0.0) and last.seq > 0

        system.wait_until(stopped, 5.0, "teleop's stop command, the last on turtle1/cmd_vel")
    finally:
        sub.undeclare()
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        os.close(fd)


def test_teleop_without_a_terminal_is_bad_input(system):
    result = system.run_cli("teleop")
    assert result.returncode == ExitCode.BAD_INPUT
    assert "teleop reads keys from a terminal, and its input is not one" in result.stderr
