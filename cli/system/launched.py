"""A launch file's system started for a test: the real ``turtlectl launch`` on a free port,
in its own process group, ready when the supervisor says every node is (its ``READY=1``
datagram in systemd's notify protocol, cli/system/supervisor/notify.py: never a sleep, never a
log line read), failed at once when a node dies while starting (with that node's output),
and always stopped: SIGINT to the group, then SIGKILL to whatever is left.  A node's exit
once the system runs is kept too (``exits``), so a test sharing a system learns of it.

``turtlectl.testing`` and its pytest plugin (``turtlectl_system``, ``turtlectl_launch``) are
thin over ``LaunchedSystem``, and so is the project's own integration harness
(tests/integration/harness.py): one way a test starts a system and knows it is ready.
"""

from __future__ import annotations

import os
import re
import selectors
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

from turtlectl.cli.system.supervisor import notify
from turtlectl.runtime.client.errors import CannotStart
from turtlectl.runtime.endpoint import LOG_DIR_ENV
from turtlectl.runtime.exitcodes import node_exit

if TYPE_CHECKING:
    from turtlectl.runtime.client.api import Client

START_LIMIT = 120.0  # s: a start that takes longer than this has hung (only a bound against hanging)
STOP_WAIT = 15.0  # s: after SIGINT, the supervisor's own shutdown (SIGINT -> SIGTERM -> SIGKILL to its nodes)


class Exit(NamedTuple):
    """A node's process ended: ``code`` (a signal: minus its number), ``ready``: after the
    system was ready."""

    node: str
    code: int
    ready: bool

    def __str__(self) -> str:
        return f"{self.node} {node_exit(self.code)}"


class StartFailed(CannotStart):
    """The system did not become ready: a node died while starting, or the launch ended."""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class LaunchedSystem:
    """``turtlectl launch LAUNCH_FILE`` on a free port (``endpoint``), started by ``start()``.

    ``args``: more options for ``launch`` (``--set navigator.goal_timeout=5``, ``--only sim``;
    with ``--tls`` the endpoint is ``tls/``); ``port``: its router's (default: a free one).  It runs in ``cwd`` (default: the launch file's
    folder), its logs in ``log_dir`` (default: a new temporary folder; the pytest plugin gives
    one under pytest's own, which pytest prunes).  ``join``: run no router of its own but join
    the one at that endpoint (``launch --connect``), which is then its ``endpoint``.
    ``on_line``: called with each line of its output as it is read (on the reader's thread)."""

    def __init__(
        self,
        launch_file: str | Path,
        args: Sequence[str] = (),
        domain: str = "",
        log_dir: str | Path | None = None,
        *,
        join: str | None = None,
        port: int | None = None,
        cwd: str | Path | None = None,
        on_line: Callable[[str], None] | None = None,
    ):
        self.launch_file = Path(launch_file).resolve()
        self.args = tuple(args)
        self.domain = domain
        self.port = port or free_port()
        scheme = "tls" if "--tls" in self.args else "tcp"
        self.join = join
        self.endpoint = join or f"{scheme}/127.0.0.1:{self.port}"
        self.cwd = Path(cwd) if cwd is not None else self.launch_file.parent
        self._on_line = on_line
        self.log_dir = Path(log_dir) if log_dir is not None else Path(tempfile.mkdtemp(prefix="turtlectl-test-logs-"))
        self.lines: list[str] = []
        self.exits: list[Exit] = []  # every node's exit the supervisor told, in order
        self._changed = threading.Condition()
        self._ready = False
        self._reading = True  # until the launch's output ends
        self._proc: subprocess.Popen[bytes] | None = None
        self._clients: list[Client] = []

    def start(self, timeout: float = START_LIMIT) -> LaunchedSystem:
        """Start it and wait until every node is ready.  StartFailed (with the node's output)
        if a node dies first, the launch ends (a launch file that does not validate: its
        message), or ``timeout`` s pass."""
        self.launch()
        return self.wait_ready(timeout)

    def launch(self) -> LaunchedSystem:
        """Start ``turtlectl launch`` and return at once (``wait_ready`` waits for its nodes)."""
        if not self.launch_file.is_file():
            raise StartFailed(f"no launch file {self.launch_file}")
        domain = ("--domain", self.domain) if self.domain else ()
        argv = [sys.executable, "-m", "turtlectl.cli", *domain, "launch", str(self.launch_file)]
        where = ("--connect", self.join) if self.join else ("--port", str(self.port))
        folder = tempfile.mkdtemp(prefix="turtlectl-notify-")  # 0700: only we write to its socket
        told = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        told.bind(os.path.join(folder, "notify"))
        env = {**os.environ, "PYTHONUNBUFFERED": "1", LOG_DIR_ENV: str(self.log_dir)}
        self._proc = subprocess.Popen(
            [*argv, *where, *self.args],
            cwd=self.cwd,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            start_new_session=True,  # its own process group: stop() reaches every node
            env={**env, notify.NOTIFY_SOCKET: told.getsockname()},
        )
        threading.Thread(target=self._read, args=(told, folder), daemon=True).start()
        return self

    @property
    def process(self) -> subprocess.Popen[bytes]:
        """The ``turtlectl launch`` process (its ``pid``, ``poll()``, ``wait()``); after ``launch``."""
        if self._proc is None:
            raise RuntimeError("not launched yet: call launch() or start()")
        return self._proc

    def wait_ready(self, timeout: float = START_LIMIT, *, fail_on_exit: bool = True) -> LaunchedSystem:
        """Wait, after ``launch``, until the supervisor says every node is ready (``READY=1``).
        StartFailed if the launch ends first or ``timeout`` s pass, and (``fail_on_exit``) if a
        node dies first, with its output."""
        deadline = time.monotonic() + timeout
        with self._changed:
            while True:
                early = [e for e in self.exits if not e.ready]  # told before READY: its ready line may follow
                if early and fail_on_exit:
                    raise StartFailed(f"{early[0]} while the system started:\n{self._output_of(early[0].node)}")
                if self._ready:
                    break
                if not self._reading:
                    code = self._proc.wait()
                    raise StartFailed(f"turtlectl launch ended (code {code}):\n{self._output()}")
                left = deadline - time.monotonic()
                if left <= 0:
                    raise StartFailed(f"not ready within {timeout:g} s:\n{self._output()}")
                self._changed.wait(left)
        return self

    def _read(self, told: socket.socket, folder: str) -> None:
        """The launch's output and its notify datagrams, on one thread: before a datagram is
        taken, the output written before it is read, so a node's exit comes with its last lines."""
        assert self._proc is not None and self._proc.stdout is not None
        out = self._proc.stdout.fileno()
        os.set_blocking(out, False)
        told.setblocking(False)
        partial = b""
        with selectors.DefaultSelector() as selector:
            selector.register(out, selectors.EVENT_READ)
            selector.register(told, selectors.EVENT_READ)
            open_ = True
            while open_:
                selector.select()
                chunks, open_ = _drain(out)
                partial = self._take_lines(partial + b"".join(chunks))
                while True:
                    try:
                        datagram = told.recv(4096)
                    except BlockingIOError:
                        break
                    self._told(notify.parse(datagram))
        told.close()
        shutil.rmtree(folder, ignore_errors=True)
        with self._changed:
            if partial:
                self.lines.append(partial.decode(errors="replace"))
            self._reading = False
            self._changed.notify_all()

    def _take_lines(self, data: bytes) -> bytes:
        *whole, rest = data.split(b"\n")
        if whole:
            lines = [line.decode(errors="replace") for line in whole]
            if self._on_line is not None:
                for line in lines:
                    self._on_line(line)
            with self._changed:
                self.lines.extend(lines)
                self._changed.notify_all()
        return rest

    def _told(self, fields: dict[str, str]) -> None:
        with self._changed:
            if fields.get("READY") == "1":
                self._ready = True
            if notify.NODE in fields:
                code = int(fields.get(notify.EXIT, "1"))
                self.exits.append(Exit(fields[notify.NODE], code, self._ready))
            self._changed.notify_all()

    def running(self) -> bool:
        """Whether the launch still runs."""
        return self._proc is not None and self._proc.poll() is None

    def output(self) -> str:
        """Everything the launch printed so far (each node's lines prefixed with its name)."""
        with self._changed:
            return self._output()

    def wait_line(self, pattern: str, timeout: float, start: int = 0) -> int:
        """The index in ``lines`` of the first line from ``start`` on that matches ``pattern`` (a
        regular expression), waiting for it up to ``timeout`` s: for a test that asserts on what
        the launch prints (its readiness is ``wait_ready``'s).  StartFailed if the launch's output
        ends without one, AssertionError when the time is up."""
        rx = re.compile(pattern)
        deadline = time.monotonic() + timeout
        ended: float | None = None  # when the launch was first seen exited: its last lines get 0.2 s
        with self._changed:
            while True:
                for i in range(start, len(self.lines)):
                    if rx.search(self.lines[i]):
                        return i
                code = self._proc.poll() if self._proc is not None else None
                if code is not None and ended is None:
                    ended = time.monotonic()
                if not self._reading or (ended is not None and time.monotonic() - ended > 0.2):
                    raise StartFailed(f"turtlectl launch ended ({code}) before {pattern!r}:\n{self._output()}")
                left = deadline - time.monotonic()
                if left <= 0:
                    raise AssertionError(f"no line matching {pattern!r} within {timeout:g} s:\n{self._output()}")
                self._changed.wait(min(left, 0.1))

    def all_output(self, timeout: float = 5.0) -> str:
        """Everything the launch printed, once its output has ended (it exited); AssertionError
        if it has not within ``timeout`` s."""
        deadline = time.monotonic() + timeout
        with self._changed:
            while self._reading:
                left = deadline - time.monotonic()
                if left <= 0:
                    raise AssertionError(f"output not closed within {timeout:g} s:\n{self._output()}")
                self._changed.wait(min(left, 0.1))
            return self._output()

    def output_of(self, node: str) -> str:
        """What ``node`` printed so far (its traceback, if it raised)."""
        with self._changed:
            return self._output_of(node)

    def _output(self) -> str:
        return "\n".join(self.lines)

    def _output_of(self, node: str) -> str:
        return "\n".join(line for line in self.lines if line.split("|", 1)[0].strip() == node)

    def client(self) -> Client:
        """A ``turtlectl.Client`` of this system (closed by ``stop``)."""
        from turtlectl.runtime.client.api import Client

        client = Client(self.endpoint, self.domain)
        self._clients.append(client)
        return client

    def stop(self) -> int | None:
        """Close its clients, SIGINT the launch (its nodes stop as on Ctrl-C), then SIGKILL the
        process group if anything is left.  The launch's exit code (None: it had to be killed)."""
        for client in self._clients:
            client.close()
        self._clients.clear()
        if self._proc is None:
            return None
        code: int | None = None
        try:
            if self._proc.poll() is None:
                os.killpg(self._proc.pid, signal.SIGINT)
            code = self._proc.wait(STOP_WAIT)
        except subprocess.TimeoutExpired:
            code = None
        except ProcessLookupError:
            code = self._proc.wait()
        finally:
            try:
                os.killpg(self._proc.pid, signal.SIGKILL)  # the group: any node left behind
            except ProcessLookupError:
                pass
            if self._proc.poll() is None:
                self._proc.wait()
        return code

    def kill(self) -> None:
        """SIGKILL the launch's process group at once and reap it (a test's cleanup when a
        graceful ``stop`` is not wanted; its nodes, in groups of their own, get SIGTERM from
        Linux as their supervisor dies)."""
        for client in self._clients:
            client.close()
        self._clients.clear()
        if self._proc is None:
            return
        try:
            os.killpg(self._proc.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
        try:
            self._proc.wait(5)
        except subprocess.TimeoutExpired:
            pass

    def __enter__(self) -> LaunchedSystem:
        try:
            return self.start()
        except BaseException:
            self.stop()
            raise

    def __exit__(self, *exc: object) -> None:
        self.stop()


def _drain(fd: int) -> tuple[list[bytes], bool]:
    """What can be read from ``fd`` now, and whether it is still open."""
    chunks = []
    while True:
        try:
            chunk = os.read(fd, 65536)
        except BlockingIOError:
            return chunks, True
        if not chunk:
            return chunks, False
        chunks.append(chunk)
