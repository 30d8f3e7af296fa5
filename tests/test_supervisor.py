"""The supervisor's decisions without processes: which signal each child gets, and when."""

from __future__ import annotations

import io
import signal

import pytest

from cli import STOPPED_BY_CTRL_C, command_of
from cli.launchfile import parse_launch
from cli.supervisor.manager import Supervisor
from cli.supervisor.printer import Printer

TWO = '[supervisor]\nsigint_timeout = 0.05\nsigterm_timeout = 0.05\n[[node]]\nname = "sim"\nrun = "sim"\n[[node]]\nname = "navigator"\nrun = "navigator"\n'


class FakeChild:
    """Records the signals it gets; exits on the first one listed in ``dies_on``."""

    def __init__(self, name: str, pid: int, dies_on: tuple[signal.Signals, ...]):
        self.name, self.pid, self.dies_on = name, pid, dies_on
        self.got: list[signal.Signals] = []
        self.alive = True

    def running(self) -> bool:
        return self.alive

    def send(self, sig: signal.Signals) -> None:
        self.got.append(sig)
        if sig in self.dies_on or sig is signal.SIGKILL:
            self.alive = False

    def flush_output(self, timeout: float = 1.0) -> None:
        pass


def supervisor_with(*children: FakeChild, ready: dict[str, int]) -> tuple[Supervisor, io.StringIO]:
    out = io.StringIO()
    sup = Supervisor(parse_launch(TWO), Printer(["sim", "navigator"], out, colour=False), 7447, "")
    sup.children = {c.name: c for c in children}  # type: ignore[misc]
    sup._alive = dict(ready)
    return sup, out


def test_a_child_still_starting_gets_sigterm_first_not_a_sigint_inside_its_imports():
    ready = FakeChild("sim", 10, (signal.SIGINT,))
    starting = FakeChild("navigator", 11, (signal.SIGTERM,))
    sup, out = supervisor_with(ready, starting, ready={"sim": 10})
    sup._shutdown()
    assert ready.got == [signal.SIGINT] and starting.got == [signal.SIGTERM]
    assert "sending" not in out.getvalue()


def test_a_respawned_child_is_ready_only_once_its_new_pid_is_announced():
    old_token = FakeChild("navigator", 12, (signal.SIGTERM,))  # the token still names pid 11
    sup, _ = supervisor_with(old_token, ready={"navigator": 11})
    sup._shutdown()
    assert old_token.got == [signal.SIGTERM]


def test_each_child_gets_each_signal_once_then_sigkill():
    stubborn_ready = FakeChild("sim", 10, ())
    stubborn_starting = FakeChild("navigator", 11, ())
    sup, out = supervisor_with(stubborn_ready, stubborn_starting, ready={"sim": 10})
    sup._shutdown()
    assert stubborn_ready.got == [signal.SIGINT, signal.SIGTERM, signal.SIGKILL]
    assert stubborn_starting.got == [signal.SIGTERM, signal.SIGKILL]
    text = out.getvalue()
    assert "sending SIGTERM to sim\n" in text and "sending SIGKILL to sim, navigator" in text


@pytest.mark.parametrize(
    "argv, command",
    [
        (["launch", "--port", "7448"], "launch"),
        (["--domain", "lab1", "launch"], "launch"),
        (["--domain=lab1", "router"], "router"),
        (["goto", "1", "2", "3"], "goto"),
        (["--version"], ""),
        ([], ""),
    ],
)
def test_the_command_of_a_command_line(argv, command):
    assert command_of(argv) == command


def test_ctrl_c_is_a_normal_stop_only_for_the_long_running_servers():
    assert STOPPED_BY_CTRL_C == ("launch", "router")
