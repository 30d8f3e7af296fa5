"""The supervisor's decisions without processes: which signal each child gets, and when."""

from __future__ import annotations

import io
import signal
import socket

import pytest

from cli import STOPPED_BY_CTRL_C, command_of
from cli.launchfile import parse_launch
from cli.supervisor import logs
from cli.supervisor.printer import Printer
from cli.supervisor.router import free_port_near, port_in_use
from cli.supervisor.supervision import Supervision

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


def supervisor_with(*children: FakeChild, ready: dict[str, int]) -> tuple[Supervision, io.StringIO]:
    out = io.StringIO()
    by_name = {c.name: c for c in children}
    sup = Supervision(parse_launch(TWO), Printer(["sim", "navigator"], out, colour=False), by_name.__getitem__)
    sup.children = dict(by_name)  # type: ignore[arg-type]
    for name, pid in ready.items():
        sup.announce(True, name, pid)
    return sup, out


def test_a_child_still_starting_gets_sigterm_first_not_a_sigint_inside_its_imports():
    ready = FakeChild("sim", 10, (signal.SIGINT,))
    starting = FakeChild("navigator", 11, (signal.SIGTERM,))
    sup, out = supervisor_with(ready, starting, ready={"sim": 10})
    sup.shutdown()
    assert ready.got == [signal.SIGINT] and starting.got == [signal.SIGTERM]
    assert "sending" not in out.getvalue()


def test_a_respawned_child_is_ready_only_once_its_new_pid_is_announced():
    old_token = FakeChild("navigator", 12, (signal.SIGTERM,))  # the token still names pid 11
    sup, _ = supervisor_with(old_token, ready={"navigator": 11})
    sup.shutdown()
    assert old_token.got == [signal.SIGTERM]


def test_each_child_gets_each_signal_once_then_sigkill():
    stubborn_ready = FakeChild("sim", 10, ())
    stubborn_starting = FakeChild("navigator", 11, ())
    sup, out = supervisor_with(stubborn_ready, stubborn_starting, ready={"sim": 10})
    sup.shutdown()
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


def test_run_folders_beyond_keep_logs_are_removed_oldest_first(tmp_path):
    names = [f"2026-01-0{d}-10-00-00-{100 + d}" for d in range(1, 8)]  # pids 101..107
    for name in names:
        (tmp_path / name).mkdir()
        (tmp_path / name / "sim.log").write_text("x")
    (tmp_path / "notes").mkdir()  # not a run folder: never touched
    (tmp_path / "2026-01-09-10-00-00-1.txt").write_text("")  # a file, not a folder
    current = logs.run_folder(tmp_path, pid=999)
    current.mkdir()
    still_running = {102}  # a launch that is still writing: kept whatever its age
    removed = logs.prune(tmp_path, 3, current, running=lambda pid: pid in still_running)
    assert sorted(p.name for p in removed) == [names[0], names[2], names[3], names[4]]
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == sorted([names[1], names[5], names[6], current.name, "notes", "2026-01-09-10-00-00-1.txt"])
    assert logs.prune(tmp_path, 0, current) == []  # 0: keep them all


def test_run_folder_names_sort_by_time_then_pid():
    assert logs.RUN_RE.match(logs.run_folder(logs.default_parent(), now=0.0, pid=42).name)
    assert logs.default_parent().parts[-2:] == (".turtlectl", "log")


def test_a_busy_port_names_the_commands_that_avoid_it():
    text = port_in_use(7447, "launch")
    assert "the port is already in use" in text
    assert '.venv/bin/turtlectl launch --port 7448 (or make run ARGS="--port 7448")' in text
    assert port_in_use(65535, "router").endswith(".venv/bin/turtlectl router --port 65534")


def test_the_port_suggested_instead_of_a_busy_one_is_free():
    """A review found `--port 7544` suggested while 7544 was taken too."""
    with socket.socket() as busy, socket.socket() as next_busy:
        busy.bind(("127.0.0.1", 0))
        port = busy.getsockname()[1]
        try:
            next_busy.bind(("127.0.0.1", port + 1))
        except OSError:
            pass  # already taken by someone else: just as good for this test
        suggested = free_port_near(port)
    assert suggested not in (port, port + 1)
