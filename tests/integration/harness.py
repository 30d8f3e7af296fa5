"""Run the real system for a test: `turtlectl launch` on a free port through
``LaunchedSystem`` (the public plugin's: ready on the supervisor's ``READY=1``), each node's pid
from its liveliness token, fail fast when the supervisor dies, and always clean up.

No fixed sleeps: every wait is on an event (a notify datagram, a token, a message, an
output line a test asserts on) under a deadline, and checks that the supervisor is still
alive while waiting.
"""

from __future__ import annotations

import fcntl
import math
import os
import pty
import queue
import re
import select
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import termios
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeVar

import msgspec
import numpy as np
import psutil
import zenoh

from turtlectl.cli.system.launched import LaunchedSystem, StartFailed
from turtlectl.cli.system.launched import free_port as free_port  # one way to pick a port
from turtlectl.messages import (
    Message,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    TeleportAbsolute,
    TurtleStatus,
    decode,
    decode_any,
    encode,
    encoding_for,
)
from turtlectl.messages.keys import NAVIGATE_TO, NODE_TOKEN_PREFIX, POSE, STATUS, TELEPORT, parse_node_token
from turtlectl.runtime.client import credentials
from turtlectl.runtime.config import NodeConfig
from turtlectl.runtime.node import Node
from turtlectl.runtime.session import client_config, close_session, peer_config, router_config

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_LAUNCH = ROOT / "launch.toml"
NODES = ("sim", "navigator", "status_monitor", "obstacle_detector")
T = TypeVar("T")


def turtlectl() -> list[str]:
    """The installed console script next to this interpreter."""
    script = Path(sys.executable).parent / "turtlectl"
    return [str(script)] if script.exists() else [sys.executable, "-m", "turtlectl.cli"]


def pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:  # a zombie is dead for our purposes
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(") ", 1)[1][0] != "Z"
    except OSError:
        return False


def read_until_closed(master: int) -> bytes:
    """Everything written to a pseudo-terminal until its last writer exits; closes ``master``."""
    out = b""
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:  # the terminal closed: the program exited
            break
        if not chunk:
            break
        out += chunk
    os.close(master)
    return out


def set_winsize(fd: int, rows: int, cols: int) -> None:
    """Give the pseudo-terminal ``fd`` a size (the program learns of it at start or by SIGWINCH)."""
    fcntl.ioctl(fd, termios.TIOCSWINSZ, struct.pack("HHHH", rows, cols, 0, 0))


def pump(fd: int, stream: Any, seconds: float) -> bool:
    """Feed what the program writes to an emulated screen (a pyte stream) for ``seconds``;
    False once it closed the terminal."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        ready, _, _ = select.select([fd], [], [], 0.05)
        if ready:
            try:
                stream.feed(os.read(fd, 65536))
            except OSError:
                return False
    return True


def session_members(sid: int) -> list[int]:
    """Live (not zombie) processes of session ``sid``: a process started with start_new_session
    and everything it ever started, wherever they were reparented."""
    members = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(") ", 1)[1].split()
            except OSError:
                continue
            if int(fields[3]) == sid and fields[0] != "Z":
                members.append(int(entry.name))
    return members


def in_pty(*args: str) -> tuple[int, int]:
    """``turtlectl ARGS`` in a new pseudo-terminal: (pid, master fd)."""
    pid, fd = pty.fork()
    if pid == 0:  # the child: the real command in a pseudo-terminal
        # a clean environment: LINES/COLUMNS (set behind os.environ's back by readline) would pin the size
        env = {k: v for k, v in os.environ.items() if k not in ("LINES", "COLUMNS")}
        env.update(TERM="xterm", LANG="C.UTF-8", LC_ALL="C.UTF-8")
        os.execve(turtlectl()[0], [*turtlectl(), *args], env)
    return pid, fd


def view_in_pty(endpoint: str) -> tuple[int, int]:
    """``turtlectl view`` in a new pseudo-terminal: (pid, master fd)."""
    return in_pty("view", "--connect", endpoint)


class Router:
    """`turtlectl router` on a free port, restartable."""

    def __init__(self):
        self.port = free_port()
        self.endpoint = f"tcp/127.0.0.1:{self.port}"
        self.proc: subprocess.Popen | None = None

    def start(self) -> None:
        self.proc = subprocess.Popen(
            [*turtlectl(), "router", "--port", str(self.port)],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()  # an event: the router says it listens
        assert "router listening" in line, line

    def kill(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(5)


class SupervisorDied(AssertionError):
    pass


class System:
    """A running `turtlectl launch` (a ``LaunchedSystem``, as ``turtlectl.testing``'s) with a
    client session to its router: ready when the supervisor says so (its ``READY=1``), each
    node's pid from its liveliness token."""

    def __init__(
        self,
        launch_file: Path = DEFAULT_LAUNCH,
        extra_args: tuple[str, ...] = (),
        join: str | None = None,
        domain: str = "",
        cwd: Path | None = None,
        port: int | None = None,
    ):
        """``join``: run no router, join the one at that endpoint.  ``domain``: the system's key prefix.
        ``cwd``: the folder it runs in (a user's project; default: this process's).  ``port``: its
        router's (default: a free one; a system started again on the port of one stopped)."""
        self.log_dir = Path(tempfile.mkdtemp(prefix="turtlectl-logs-"))
        self.child_pids: dict[int, float] = {}  # pid -> its start time, so a reused pid is never killed
        self.launched = LaunchedSystem(
            launch_file,
            extra_args,
            domain,
            self.log_dir,
            join=join,
            port=port or free_port(),  # this module's: a bench may choose its own range
            cwd=cwd or Path.cwd(),
            on_line=self._on_line,
        )
        self.port = self.launched.port
        self.endpoint = self.launched.endpoint
        self.domain = domain
        self.lines = self.launched.lines  # the launch's output, as it is read
        self.proc = self.launched.launch().process
        self.session: zenoh.Session | None = None
        self.alive: dict[str, int] = {}  # node -> pid, from liveliness
        self._token_events: queue.SimpleQueue[tuple[bool, str, int]] = queue.SimpleQueue()

    def _remember(self, pid: int) -> None:
        """Note a child of the system with its start time (gone already: nothing to kill later)."""
        if pid not in self.child_pids:
            try:
                self.child_pids[pid] = psutil.Process(pid).create_time()
            except psutil.Error:
                pass

    # -- output ---------------------------------------------------------------
    def _on_line(self, line: str) -> None:
        m = re.search(r"started \S+ \(pid (\d+)\)", line)  # every child, to kill at the end whatever happens
        if m:
            self._remember(int(m.group(1)))

    def output(self) -> str:
        return self.launched.output()

    def all_output(self, timeout: float = 5.0) -> str:
        """Everything the supervisor wrote, once it has exited and its output is read to the end."""
        return self.launched.all_output(timeout)

    def check_alive(self) -> None:
        if self.proc.poll() is not None:
            raise SupervisorDied(f"turtlectl launch exited with {self.proc.returncode}:\n{self.output()}")

    def wait_line(self, pattern: str, timeout: float, start: int = 0) -> int:
        """Index of the first output line from ``start`` matching ``pattern`` (for a test that
        asserts on what the launch prints; readiness is ``wait_ready``'s)."""
        try:
            return self.launched.wait_line(pattern, timeout, start)
        except StartFailed as exc:
            raise SupervisorDied(str(exc)) from None

    # -- readiness -------------------------------------------------------------
    def connect(self, timeout: float = 20.0) -> zenoh.Session:
        """A client session to the system's router, once the supervisor says its nodes are ready
        (its ``READY=1``: the router listens long before), and their liveliness tokens followed."""
        try:
            self.launched.wait_ready(timeout, fail_on_exit=False)  # a node that fails is the test's to see
        except StartFailed as exc:
            raise SupervisorDied(str(exc)) from None
        login = credentials.for_endpoint(self.endpoint)  # a --secure system's, from TURTLECTL_CREDENTIALS
        self.session = zenoh.open(client_config(self.endpoint, 3.0, self.domain, login))
        self.session.liveliness().declare_subscriber(f"{NODE_TOKEN_PREFIX}/**", self._on_token, history=True)
        return self.session

    def _on_token(self, sample: zenoh.Sample) -> None:
        info = parse_node_token(str(sample.key_expr))
        if info:
            self._token_events.put((sample.kind == zenoh.SampleKind.PUT, info.name, info.pid))

    def _drain_tokens(self, wait: float) -> None:
        try:
            item = self._token_events.get(timeout=wait)
        except queue.Empty:
            return
        while item is not None:
            up, name, pid = item
            if up:
                self.alive[name] = pid
                self._remember(pid)
            elif self.alive.get(name) == pid:
                del self.alive[name]
            try:
                item = self._token_events.get_nowait()
            except queue.Empty:
                item = None

    def wait_until(self, condition: Callable[[], bool], timeout: float, what: str) -> None:
        """Wait for ``condition`` (re-checked as liveliness events arrive) under a deadline."""
        deadline = time.monotonic() + timeout
        while not condition():
            self.check_alive()
            if time.monotonic() > deadline:
                raise AssertionError(
                    f"timed out after {timeout} s waiting for {what}; alive={self.alive}\n{self.output()}"
                )
            self._drain_tokens(0.05)

    def wait_ready(self, names: tuple[str, ...] = NODES, timeout: float = 30.0) -> dict[str, int]:
        if self.session is None:
            self.connect(timeout)
        self.wait_until(lambda: set(names) <= set(self.alive), timeout, f"nodes {names}")
        return dict(self.alive)

    # -- traffic -----------------------------------------------------------
    def collect(self, key: str, msg_type: type[T], count: int, timeout: float) -> list[tuple[float, T]]:
        """``count`` messages on ``key`` with their arrival times (monotonic s)."""
        assert self.session is not None
        got: queue.SimpleQueue[tuple[float, bytes]] = queue.SimpleQueue()
        sub = self.session.declare_subscriber(key, lambda s: got.put((time.monotonic(), s.payload.to_bytes())))
        out: list[tuple[float, T]] = []
        deadline = time.monotonic() + timeout
        try:
            while len(out) < count:
                self.check_alive()
                if time.monotonic() > deadline:
                    raise AssertionError(f"only {len(out)} of {count} messages on {key} within {timeout} s")
                try:
                    t, payload = got.get(timeout=0.1)
                except queue.Empty:
                    continue
                out.append((t, decode(payload, msg_type)))
        finally:
            sub.undeclare()
        return out

    def call(self, key: str, request: Message, timeout: float = 10.0, everyone: bool = False) -> list[zenoh.Reply]:
        """Every reply to ``request`` (no consolidation: feedback and answers)."""
        assert self.session is not None
        return list(
            self.session.get(
                key,
                payload=encode(request),
                encoding=zenoh.Encoding(encoding_for(type(request))),
                consolidation=zenoh.ConsolidationMode.NONE,
                target=zenoh.QueryTarget.ALL if everyone else zenoh.QueryTarget.BEST_MATCHING,
                timeout=timeout,
            )
        )

    def navigate(
        self, x: float, y: float, theta: float, timeout: float = 20.0
    ) -> tuple[NavigateToResponse, float, list[NavigateToFeedback]]:
        """Run a goal to its end: (response, seconds measured here, feedback received)."""
        started = time.monotonic()
        replies = self.call(NAVIGATE_TO, NavigateToRequest(x=x, y=y, theta=theta), timeout)
        elapsed = time.monotonic() - started
        errors = [r.err.payload.to_bytes() for r in replies if r.err is not None]
        assert replies and not errors, f"navigate_to ({x}, {y}, {theta}): error replies {errors}"
        messages = [decode_any(r.ok.payload.to_bytes()) for r in replies]
        final = [m for m in messages if isinstance(m, NavigateToResponse)]
        assert len(final) == 1 and messages[-1] is final[0], messages
        return final[0], elapsed, [m for m in messages if isinstance(m, NavigateToFeedback)]

    def latest_pose(self) -> Pose:
        return self.collect(POSE, Pose, 1, timeout=5.0)[0][1]

    def wait_moving(self, speed: float = 0.5, timeout: float = 10.0) -> Pose:
        """The first pose showing the turtle faster than ``speed`` m/s (an event, not a sleep)."""
        deadline = time.monotonic() + timeout
        while True:
            pose = self.latest_pose()
            if abs(pose.linear_velocity) > speed:
                return pose
            assert time.monotonic() < deadline, f"the turtle never reached {speed} m/s: {pose}"

    def wait_stopped(self, timeout: float = 3.0) -> Pose:
        """The first pose showing the turtle at rest."""
        deadline = time.monotonic() + timeout
        while True:
            pose = self.latest_pose()
            if pose.linear_velocity == 0.0 and pose.angular_velocity == 0.0:
                return pose
            assert time.monotonic() < deadline, f"the turtle did not stop within {timeout} s: {pose}"

    def teleport(self, x: float, y: float, theta: float) -> None:
        """Put the turtle at (x, y) m facing theta rad, and wait until the pose says so."""
        replies = self.call(TELEPORT, TeleportAbsolute(x=x, y=y, theta=theta))
        assert len(replies) == 1 and replies[0].ok is not None, replies
        deadline = time.monotonic() + 5.0
        while True:
            pose = self.latest_pose()
            if math.hypot(pose.x - x, pose.y - y) < 1e-6 and pose.linear_velocity == 0.0:
                return
            assert time.monotonic() < deadline, f"pose {pose} never showed the teleport to {(x, y, theta)}"

    def run_cli(self, *args: str, timeout: float = 30.0) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [*turtlectl(), *(("--domain", self.domain) if self.domain else ()), *args, "--connect", self.endpoint],
            capture_output=True,
            text=True,
            timeout=timeout,
            stdin=subprocess.DEVNULL,
        )

    # -- teardown ------------------------------------------------------------
    def stop(self, sig: int = signal.SIGINT, timeout: float = 8.0) -> int:
        """Signal the supervisor and wait for it; returns its exit code."""
        if self.proc.poll() is None:
            os.kill(self.proc.pid, sig)
        try:
            return self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            raise AssertionError(f"launch did not stop within {timeout} s after {sig}:\n{self.output()}") from None

    def kill_everything(self) -> None:
        """Always: close our session, kill the supervisor's group and every child seen."""
        if self.session is not None:
            close_session(self.session)
            self.session = None
        self.launched.kill()
        for pid, started in self.child_pids.items():
            try:  # only the process seen then: after hours of tests a pid is reused (pid_max 32768 here)
                if psutil.Process(pid).create_time() == started:
                    os.kill(pid, signal.SIGKILL)
            except (psutil.Error, ProcessLookupError, PermissionError):
                pass
        shutil.rmtree(self.log_dir, ignore_errors=True)


@contextmanager
def running_system(
    launch_file: Path = DEFAULT_LAUNCH, ready: tuple[str, ...] = NODES, **options: Any
) -> Iterator[System]:
    system = System(launch_file, **options)
    try:
        if ready:
            system.wait_ready(ready)
            if "status_monitor" in ready:  # readiness of the data path: a status has flowed
                system.collect(STATUS, TurtleStatus, 1, timeout=10.0)
        else:
            system.connect()
        yield system
    finally:
        system.kill_everything()


def obstacles_in_view(ranges: np.ndarray, angles: np.ndarray) -> int:
    """Number of separate objects the scan sees: runs of consecutive finite beams."""
    finite = np.isfinite(np.asarray(ranges, dtype=float))
    if not finite.any():
        return 0
    # count rising edges, treating the scan as circular only if it is a full circle
    edges = np.count_nonzero(finite & ~np.roll(finite, 1))
    return int(edges) if edges else 1


class NoParams(msgspec.Struct):
    """The parameters of a node made in a test's own process: none."""


@contextmanager
def node_in_process(name: str) -> Iterator[tuple[Node[NoParams], zenoh.Session]]:
    """A Node (a peer session) and a client session, both on a router opened here, in the
    test's own process: the test runs what the node queued itself, as the node's thread would
    (``node.spin_once``, ``node.spin_until``; ``node.core.drain()`` without waiting)."""
    port = free_port()
    endpoint = f"tcp/127.0.0.1:{port}"
    router = zenoh.open(router_config(port))
    peer = zenoh.open(peer_config(endpoint))
    client = zenoh.open(client_config(endpoint, 5.0))
    try:
        yield Node(NodeConfig(name=name, kind="test", connect=endpoint), NoParams(), peer), client
    finally:
        for session in (client, peer, router):
            close_session(session)


@contextmanager
def credentials_at(path: Path) -> Iterator[Path]:
    """``TURTLECTL_CREDENTIALS`` set to ``path`` while the block runs (a test's secure systems write their
    logins there, never in the user's own file), restored after."""
    before = os.environ.get(credentials.ENV)
    os.environ[credentials.ENV] = str(path)
    try:
        yield path
    finally:
        if before is None:
            del os.environ[credentials.ENV]
        else:
            os.environ[credentials.ENV] = before
