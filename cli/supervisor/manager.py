"""The supervisor: runs a router, starts every node of a launch plan, watches them,
and stops them all, in order, on request or when a required node dies.

Shutdown escalates SIGINT -> SIGTERM -> SIGKILL with bounded waits, so the
whole system is down within ``SHUTDOWN_BUDGET`` seconds and no child outlives
the supervisor.  Never prints directly: everything goes through the Printer.
"""

from __future__ import annotations

import os
import queue
import signal
import time
from typing import Any

import zenoh

from cli.errors import CliError, ExitCode
from cli.launchfile import LaunchPlan, node_config
from cli.supervisor.printer import Printer
from cli.supervisor.process import Child, child_env, python_module_argv
from messages.keys import NODE_TOKEN_PREFIX, parse_node_token
from nodes.config import ENV_VAR, SUPERVISOR_PID_VAR, encode_config
from nodes.kinds import KINDS
from nodes.session import close_session, router_config

POLL = 0.05  # s between checks of the children
SIGINT_WAIT = 2.0  # s for children to stop after SIGINT
SIGTERM_WAIT = 1.0  # s after SIGTERM, before SIGKILL
SHUTDOWN_BUDGET = 5.0  # s: the most a shutdown may take


class Supervisor:
    def __init__(self, plan: LaunchPlan, port: int, printer: Printer):
        self.plan = plan
        self.port = port
        self.endpoint = f"tcp/127.0.0.1:{port}"
        self.printer = printer
        self.children: dict[str, Child] = {}
        self.entries = {e.name: e for e in plan.launch.node}
        self._respawn_at: dict[str, float] = {}
        self._stop_reason: str | None = None
        self._exit_code = ExitCode.OK
        self._events: queue.SimpleQueue[tuple[bool, str, int]] = queue.SimpleQueue()
        self._alive: dict[str, int] = {}  # node name -> pid announced by liveliness
        self._ready_reported = False
        self._t0 = time.monotonic()

    # -- lifecycle ----------------------------------------------------------
    def run(self) -> int:
        """Run until stopped; returns the exit code. Raises CliError if it cannot start."""
        try:
            session = zenoh.open(router_config(self.port))
        except zenoh.ZError as exc:
            reason = "the port is already in use" if "in use" in str(exc) else str(exc)
            raise CliError(
                ExitCode.CANNOT_START,
                f"cannot listen on {self.endpoint}: {reason} (another `turtlectl launch`? try --port)",
            ) from None
        previous = {sig: signal.signal(sig, self._on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
        try:
            watcher = session.liveliness().declare_subscriber(f"{NODE_TOKEN_PREFIX}/**", self._on_token, history=True)
            count = len(self.entries)
            self.printer.system(f"router listening on {self.endpoint}; starting {count} node{'s' * (count != 1)}")
            for name in self.entries:
                self._start(name)
            self._watch()
            self._shutdown()
            watcher.undeclare()
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
        info = parse_node_token(str(sample.key_expr))
        if info is not None:
            self._events.put((sample.kind == zenoh.SampleKind.PUT, info.name, info.pid))

    # -- children -----------------------------------------------------------
    def _child(self, name: str) -> Child:
        """The Child for node ``name``: its command and environment, made once."""
        config = node_config(self.plan, name, self.endpoint)
        env = child_env({ENV_VAR: encode_config(config), SUPERVISOR_PID_VAR: str(os.getpid())})
        return Child(name, python_module_argv(KINDS[config.kind].module), env, self.printer)

    def _start(self, name: str) -> None:
        child = self.children.get(name) or self.children.setdefault(name, self._child(name))
        child.start()
        self.printer.system(f"started {name} (pid {child.pid})")

    def _watch(self) -> None:
        while self._stop_reason is None:
            self._drain_events()
            now = time.monotonic()
            for name, child in self.children.items():
                if name in self._respawn_at:
                    if now >= self._respawn_at[name]:
                        del self._respawn_at[name]
                        self._start(name)
                    continue
                code = child.poll()
                if code is None:
                    continue
                child.flush_output()
                entry = self.entries[name]
                how = f"exited with code {code}" if code >= 0 else f"was killed by {signal.Signals(-code).name}"
                if entry.required:
                    self.printer.system(f"{name} {how}; it is required, stopping the system")
                    self.stop(f"required node {name} {how}", ExitCode.FAILED)
                    break
                if entry.respawn:
                    self.printer.system(f"{name} {how}; respawning in {entry.respawn_delay:g} s")
                    self._respawn_at[name] = now + entry.respawn_delay
                else:
                    self.printer.system(f"{name} {how}")
            if self._stop_reason is None and not self._respawn_at and not any(
                c.running() for c in self.children.values()
            ):
                self.stop("every node has exited", ExitCode.FAILED)
            time.sleep(POLL)  # pacing: the supervisor's poll period

    def _drain_events(self) -> None:
        while True:
            try:
                alive, name, pid = self._events.get_nowait()
            except queue.Empty:
                return
            if alive:
                self._alive[name] = pid
            elif self._alive.get(name) == pid:
                del self._alive[name]
            if not self._ready_reported and set(self.entries) <= set(self._alive):
                self._ready_reported = True
                elapsed = time.monotonic() - self._t0
                count = len(self.entries)
                self.printer.system(f"{'all ' * (count > 1)}{count} node{'s' * (count != 1)} ready in {elapsed:.2f} s")

    def _shutdown(self) -> None:
        """SIGINT, wait, SIGTERM, wait, SIGKILL: each child gets each signal once."""
        deadline = time.monotonic() + SHUTDOWN_BUDGET
        steps = ((signal.SIGINT, SIGINT_WAIT), (signal.SIGTERM, SIGTERM_WAIT), (signal.SIGKILL, 1.0))
        for sig, wait in steps:
            targets = [c for c in self.children.values() if c.running()]
            if not targets:
                break
            if sig is not signal.SIGINT:
                self.printer.system(f"sending {sig.name} to {', '.join(c.name for c in targets)}")
            for child in targets:
                child.send(sig)
            until = min(time.monotonic() + wait, deadline)
            while time.monotonic() < until and any(c.running() for c in targets):
                time.sleep(0.02)  # pacing: reaping children
        for child in self.children.values():
            child.flush_output(0.2)
