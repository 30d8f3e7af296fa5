"""The supervisor: runs a router (or joins one), starts every node of a launch plan,
watches them, respawns them with backoff, and stops them all, in order, on
request or when a required node is gone for good.

Shutdown escalates SIGINT -> SIGTERM -> SIGKILL with the launch file's waits,
each child getting each signal once, and no child outlives the supervisor.  A
child that has not announced itself yet is still importing and gets SIGTERM
first: a SIGINT there raises KeyboardInterrupt inside an import (a traceback).
Never prints directly: everything goes through the Printer.
"""

from __future__ import annotations

import os
import queue
import signal
import socket
import time
from pathlib import Path
from typing import Any

import zenoh

from cli.errors import CliError, ExitCode
from cli.launchfile import LaunchPlan, node_config
from cli.supervisor import logs
from cli.supervisor.printer import Printer
from cli.supervisor.process import Child, node_command
from messages.keys import NODE_TOKEN_PREFIX, domain_token, parse_node_token
from runtime.session import client_config, close_session, router_config, zenoh_reason

POLL = 0.05  # s between checks of the children
STABLE_RUN = 10.0  # s: a child that ran this long has its respawn count reset
KILL_WAIT = 1.0  # s for the kernel to reap SIGKILLed children


def respawn_delay(first: float, cap: float, attempt: int) -> float:
    """Delay (s) before respawn number ``attempt`` (1, 2, …): doubling from ``first``, at most ``cap``."""
    return min(cap, first * 2.0 ** (attempt - 1)) if first > 0 else 0.0


def free_port_near(port: int, host: str = "127.0.0.1") -> int:
    """The first port after ``port`` (wrapping below it at the top) that ``host`` can listen on now."""
    candidates = [p for p in range(port + 1, min(port + 50, 65536))] + list(range(port - 1, max(port - 50, 0), -1))
    for candidate in candidates:
        with socket.socket() as probe:
            try:
                probe.bind((host.strip("[]"), candidate))
            except OSError:
                continue
            return candidate
    return port + 1 if port < 65535 else port - 1


def port_in_use(port: int, command: str, host: str = "127.0.0.1") -> str:
    """Why a listen failed on a busy port, and the command that avoids it (with a port that is free now)."""
    other = free_port_near(port, host)
    if command == "launch":
        how = f'.venv/bin/turtlectl launch --port {other} (or make run ARGS="--port {other}")'
    else:
        how = f".venv/bin/turtlectl {command} --port {other}"
    return f"the port is already in use (another `turtlectl {command}`?); choose another: {how}"


class Supervisor:
    """``port`` given: run a router on ``host``:port.  ``port`` None: join the router at ``connect``.
    ``log_parent``: where this run's log folder goes, made once the router is up (None: no files)."""

    def __init__(
        self,
        plan: LaunchPlan,
        printer: Printer,
        port: int | None,
        connect: str,
        domain: str = "",
        host: str = "127.0.0.1",
        log_parent: Path | None = None,
    ):
        self.plan = plan
        self.log_parent = log_parent
        self.port = port
        self.host = host
        self.endpoint = f"tcp/{host}:{port}" if port is not None else connect
        self.domain = domain
        self.printer = printer
        self.children: dict[str, Child] = {}
        self.entries = {e.name: e for e in plan.launch.node}
        self._respawn_at: dict[str, float] = {}
        self._crashes: dict[str, int] = {}  # respawns in a row, per node
        self._given_up: set[str] = set()  # nodes that exited for good: no longer watched
        self._stop_reason: str | None = None
        self._exit_code = ExitCode.OK
        self._events: queue.SimpleQueue[tuple[bool, str, int]] = queue.SimpleQueue()
        self._alive: dict[str, int] = {}  # node name -> pid announced by liveliness
        self._ready_reported = False
        self._t0 = time.monotonic()

    # -- lifecycle ----------------------------------------------------------
    def _open(self) -> zenoh.Session:
        if self.port is None:
            try:
                return zenoh.open(client_config(self.endpoint, 3.0))
            except zenoh.ZError:
                raise CliError(ExitCode.UNREACHABLE, f"no router at {self.endpoint} to join") from None
        try:
            return zenoh.open(router_config(self.port, self.host))
        except zenoh.ZError as exc:
            if "in use" in str(exc):
                reason = port_in_use(self.port, "launch", self.host)
            else:
                reason = zenoh_reason(exc)
            raise CliError(ExitCode.CANNOT_START, f"cannot listen on {self.endpoint}: {reason}") from None

    def _open_logs(self) -> None:
        """This run's log folder, made only now that the router is up (a launch that cannot
        start leaves nothing behind), and the oldest run folders beyond keep_logs removed."""
        if self.log_parent is None:
            self.printer.system(f"launch file {self.plan.source}")
            return
        folder = logs.run_folder(self.log_parent)
        names = [e.name for e in self.plan.launch.node]
        try:
            self.printer.log_to(folder, names)
        except OSError as exc:
            raise CliError(ExitCode.CANNOT_START, f"cannot write logs to {folder}: {exc.strerror or exc}") from None
        self.printer.system(f"launch file {self.plan.source}; logs in {folder}")
        try:
            logs.prune(self.log_parent, self.plan.launch.supervisor.keep_logs, folder)
        except OSError as exc:
            self.printer.system(
                f"warning: could not remove old run folders in {self.log_parent}: {exc.strerror or exc}"
            )

    def run(self) -> int:
        """Run until stopped; returns the exit code. Raises CliError if it cannot start."""
        session = self._open()
        try:
            self._open_logs()
        except CliError:
            close_session(session)
            raise
        previous = {sig: signal.signal(sig, self._on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
        try:
            prefix = f"{self.domain}/" if self.domain else ""
            watcher = session.liveliness().declare_subscriber(
                f"{prefix}{NODE_TOKEN_PREFIX}/**", self._on_token, history=True
            )
            # outside the namespace (this session has none): clients without --domain find the domain
            announced = session.liveliness().declare_token(domain_token(self.domain)) if self.domain else None
            count = len(self.entries)
            where = f"router listening on {self.endpoint}" if self.port is not None else f"joining {self.endpoint}"
            domain = f" in domain {self.domain!r}" if self.domain else ""
            self.printer.system(f"{where}{domain}; starting {count} node{'s' * (count != 1)}")
            for name in self.entries:
                if self._stop_reason is not None:  # stopped while starting: start no more
                    break
                self._start(name)
            self._watch()
            self._shutdown()
            watcher.undeclare()
            if announced is not None:
                announced.undeclare()
        finally:
            for sig, handler in previous.items():
                signal.signal(sig, handler)
            if not close_session(session):
                self.printer.system("router session did not close in time")
        self.printer.system(f"stopped ({self._stop_reason}); exit code {int(self._exit_code)}")
        return int(self._exit_code)

    def stop(self, reason: str, code: ExitCode = ExitCode.OK) -> None:
        if self._stop_reason is None:
            self._stop_reason = reason
            self._exit_code = code

    def _on_signal(self, signum: int, _frame: Any) -> None:
        self.stop(f"received {signal.Signals(signum).name}")

    def _on_token(self, sample: zenoh.Sample) -> None:  # Zenoh thread: queue only
        key = str(sample.key_expr)
        if self.domain:
            key = key.removeprefix(f"{self.domain}/")
        info = parse_node_token(key)
        if info is not None:
            self._events.put((sample.kind == zenoh.SampleKind.PUT, info.name, info.pid))

    # -- children -----------------------------------------------------------
    def _child(self, name: str) -> Child:
        """The Child for node ``name``: its command and environment, made once."""
        config = node_config(self.plan, name, self.endpoint, domain=self.domain)
        argv, env = node_command(config, supervisor_pid=os.getpid())
        return Child(name, argv, env, self.printer)

    def _start(self, name: str) -> None:
        child = self.children.get(name) or self.children.setdefault(name, self._child(name))
        child.start()
        self.printer.system(f"started {name} (pid {child.pid})")

    def _watch(self) -> None:
        while self._stop_reason is None:
            self._drain_events()
            now = time.monotonic()
            for name, child in self.children.items():
                if name in self._given_up:
                    continue
                if name in self._respawn_at:
                    if now >= self._respawn_at[name]:
                        del self._respawn_at[name]
                        self._start(name)
                    continue
                code = child.poll()
                if code is not None:
                    self._exited(name, child, code, now)
                    if self._stop_reason is not None:
                        break
            if (
                self._stop_reason is None
                and not self._respawn_at
                and not any(c.running() for c in self.children.values())
            ):
                self.stop("every node has exited", ExitCode.FAILED)
            time.sleep(POLL)  # pacing: the supervisor's poll period

    def _exited(self, name: str, child: Child, code: int, now: float) -> None:
        """Decide what a child's exit means: respawn it (with backoff), or give up on it."""
        child.flush_output()
        entry = self.entries[name]
        how = f"exited with code {code}" if code >= 0 else f"was killed by {signal.Signals(-code).name}"
        if now - child.started_at >= STABLE_RUN:
            self._crashes[name] = 0
        crashes = self._crashes.get(name, 0)
        if entry.respawn and (entry.respawn_max == 0 or crashes < entry.respawn_max):
            self._crashes[name] = crashes + 1
            delay = respawn_delay(entry.respawn_delay, entry.respawn_delay_max, crashes + 1)
            self.printer.system(f"{name} {how}; respawning in {delay:g} s (respawn {crashes + 1})")
            self._respawn_at[name] = now + delay
            return
        self._given_up.add(name)
        if entry.respawn:
            how += f", after {crashes} respawns in a row; giving up on it"
        if entry.required:
            self.printer.system(f"{name} {how}; it is required, stopping the system")
            self.stop(f"required node {name} {how}", ExitCode.FAILED)
        else:
            self.printer.system(f"{name} {how}")

    def _drain_events(self) -> None:
        while True:
            try:
                alive, name, pid = self._events.get_nowait()
            except queue.Empty:
                return
            child = self.children.get(name)
            if alive and child is not None and child.pid != pid and child.running():
                self.printer.system(
                    f"warning: another process (pid {pid}) also calls itself {name}; `turtlectl list` shows both"
                )
            if alive:
                self._alive[name] = pid
            elif self._alive.get(name) == pid:
                del self._alive[name]
            if not self._ready_reported and set(self.entries) <= set(self._alive):
                self._ready_reported = True
                elapsed = time.monotonic() - self._t0
                count = len(self.entries)
                self.printer.system(f"{'all ' * (count > 1)}{count} node{'s' * (count != 1)} ready in {elapsed:.2f} s")

    def _ready(self, child: Child) -> bool:
        """True once this very process of the node has announced itself (liveliness token)."""
        return child.pid is not None and self._alive.get(child.name) == child.pid

    def _shutdown(self) -> None:
        """SIGINT, wait, SIGTERM, wait, SIGKILL: each child gets each signal at most once.

        A child not ready yet is still starting (importing numpy and zenoh), where SIGINT
        would raise KeyboardInterrupt and print a traceback: it gets SIGTERM at the first
        step instead, which ends it silently (the default action) or, once the node runtime
        has installed its handler, stops it as SIGINT does.
        """
        self._drain_events()
        settings = self.plan.launch.supervisor
        steps = (
            (signal.SIGINT, settings.sigint_timeout),
            (signal.SIGTERM, settings.sigterm_timeout),
            (signal.SIGKILL, KILL_WAIT),
        )
        sent: dict[str, set[signal.Signals]] = {name: set() for name in self.children}
        for sig, wait in steps:
            targets = [c for c in self.children.values() if c.running()]
            if not targets:
                break
            sends = []
            for child in targets:
                first = signal.SIGTERM if sig is signal.SIGINT and not self._ready(child) else sig
                if first not in sent[child.name]:
                    sends.append((child, first))
            escalated = [c.name for c, s in sends if sig is not signal.SIGINT]
            if escalated:
                self.printer.system(f"sending {sig.name} to {', '.join(escalated)}")
            for child, first in sends:
                child.send(first)
                sent[child.name].add(first)
            until = time.monotonic() + wait
            while time.monotonic() < until and any(c.running() for c in targets):
                time.sleep(0.02)  # pacing: reaping children
        for child in self.children.values():
            child.flush_output(0.2)
