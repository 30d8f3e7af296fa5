"""A launch file's system started for a test: the real ``turtlectl launch`` on a free port,
in its own process group, ready when the supervisor says every node is (liveliness tokens,
never a sleep), failed at once when a node dies while starting (with that node's output),
and always stopped: SIGINT to the group, then SIGKILL to whatever is left.

``turtlectl.testing`` and its pytest plugin (``turtlectl_system``, ``turtlectl_launch``) are
thin over ``LaunchedSystem``.
"""

from __future__ import annotations

import os
import re
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from turtlectl.cli.errors import CannotStart

if TYPE_CHECKING:
    from turtlectl.cli.tools.api import Client

READY = re.compile(r"^launch\s*\| (?:all )?\d+ nodes? ready in ")
DIED = re.compile(r"^launch\s*\| (\S+) (exited with code \d+|was killed by \w+)")
START_LIMIT = 120.0  # s: a start that takes longer than this has hung (only a bound against hanging)
STOP_WAIT = 15.0  # s: after SIGINT, the supervisor's own shutdown (SIGINT -> SIGTERM -> SIGKILL to its nodes)


class StartFailed(CannotStart):
    """The system did not become ready: a node died while starting, or the launch ended."""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class LaunchedSystem:
    """``turtlectl launch LAUNCH_FILE`` on a free port (``endpoint``), started by ``start()``.

    ``args``: more options for ``launch`` (``--set navigator.goal_timeout=5``, ``--only sim``).
    It runs in the launch file's folder, its logs in ``log_dir`` (default: a new temporary folder;
    the pytest plugin gives one under pytest's own, which pytest prunes)."""

    def __init__(
        self, launch_file: str | Path, args: Sequence[str] = (), domain: str = "", log_dir: str | Path | None = None
    ):
        self.launch_file = Path(launch_file).resolve()
        self.args = tuple(args)
        self.domain = domain
        self.port = free_port()
        self.endpoint = f"tcp/127.0.0.1:{self.port}"
        self.log_dir = Path(log_dir) if log_dir is not None else Path(tempfile.mkdtemp(prefix="turtlectl-test-logs-"))
        self.lines: list[str] = []
        self._changed = threading.Condition()
        self._ready = False
        self._died: tuple[str, str] | None = None  # (node, how) of the first death before ready
        self._reading = True  # until the launch's output ends
        self._proc: subprocess.Popen[str] | None = None
        self._clients: list[Client] = []

    def start(self, timeout: float = START_LIMIT) -> LaunchedSystem:
        """Start it and wait until every node is ready.  StartFailed (with the node's output)
        if a node dies first, the launch ends (a launch file that does not validate: its
        message), or ``timeout`` s pass."""
        if not self.launch_file.is_file():
            raise StartFailed(f"no launch file {self.launch_file}")
        domain = ("--domain", self.domain) if self.domain else ()
        argv = [sys.executable, "-m", "turtlectl.cli", *domain, "launch", str(self.launch_file)]
        self._proc = subprocess.Popen(
            [*argv, "--port", str(self.port), *self.args],
            cwd=self.launch_file.parent,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            start_new_session=True,  # its own process group: stop() reaches every node
            text=True,
            env={**os.environ, "PYTHONUNBUFFERED": "1", "TURTLECTL_LOG_DIR": str(self.log_dir)},
        )
        threading.Thread(target=self._read, daemon=True).start()
        deadline = time.monotonic() + timeout
        with self._changed:
            while not self._ready:
                if self._died is not None:
                    name, how = self._died
                    raise StartFailed(f"{name} {how} while the system started:\n{self.output_of(name)}")
                if self._proc.poll() is not None and not self._reading:
                    raise StartFailed(f"turtlectl launch ended (code {self._proc.returncode}):\n{self.output()}")
                left = deadline - time.monotonic()
                if left <= 0:
                    raise StartFailed(f"not ready within {timeout:g} s:\n{self.output()}")
                self._changed.wait(left)
        return self

    def _read(self) -> None:
        assert self._proc is not None and self._proc.stdout is not None
        for line in self._proc.stdout:
            line = line.rstrip("\n")
            with self._changed:
                self.lines.append(line)
                if READY.match(line):
                    self._ready = True
                died = DIED.match(line)
                if died and not self._ready and self._died is None:
                    self._died = (died.group(1), died.group(2))
                self._changed.notify_all()
        with self._changed:
            self._reading = False
            self._changed.notify_all()

    def output(self) -> str:
        """Everything the launch printed so far (each node's lines prefixed with its name)."""
        with self._changed:
            return "\n".join(self.lines)

    def output_of(self, node: str) -> str:
        """What ``node`` printed so far (its traceback, if it raised)."""
        with self._changed:
            return "\n".join(line for line in self.lines if line.split("|", 1)[0].strip() == node)

    def client(self) -> Client:
        """A ``turtlectl.Client`` of this system (closed by ``stop``)."""
        from turtlectl.cli.tools.api import Client

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

    def __enter__(self) -> LaunchedSystem:
        try:
            return self.start()
        except BaseException:
            self.stop()
            raise

    def __exit__(self, *exc: object) -> None:
        self.stop()
