"""The supervision policy: what to do with the children of a launch plan, with no Zenoh and
no real process (they come from a factory, time from a clock and a sleep function), so
every rule is tested with fake children and a fake clock (tests/unit/cli/system/supervisor).

* Start every node in the plan's order; a stop requested meanwhile starts no more.
* A child that exits is respawned if its entry says so: first after respawn_delay s, then
  twice as long each time up to respawn_delay_max s, at most respawn_max times in a row (0:
  no limit); a run of STABLE_RUN s or more starts the count again.  Not after an exit that
  the next start would repeat (runtime.exitcodes.respawn_can_help: 2, its configuration
  cannot be used; 4, another process holds what it claims): given up on at once, one line
  saying why.
* A start limit, as systemd's: a child that exits before it is ready (its constructor raises,
  its module cannot import) start_tries times in a row is not respawned again, one line saying
  why (how many tries, its last line of output, its log file).  Only the first of those starts
  shows its output on the terminal (the traceback once); the others go to its log file.
* A child that exits for good (no respawn, respawns used up, its start limit) is given up on;
  if it is required the system stops, exit code FAILED.  So does a system whose every node has
  exited.  A system stopped on request while a node has failed to start (given up on, or still
  being retried), or has been lost for good (it ran, then exited with an error or a signal and
  was given up on: no respawn, respawns used up), exits FAILED too, its stop reason naming the
  node: the system was incomplete.  A node that ended its work (exit 0) is not lost.
* Readiness comes from outside (``announce``, from any thread): a child is ready once this
  very process (its pid) has announced itself; a ``cmd`` node (any program: it announces
  nothing) is ready once started.  The ready line comes once every node is ready or has failed
  to start (not waiting out its respawns), naming those that never started.  An announcement under a node's name from
  any other pid (another system's node joined through --connect, an earlier start) counts
  for nothing: not towards "ready", nor against it when it goes away.
* Shutdown escalates SIGINT -> SIGTERM -> SIGKILL with the launch file's waits, each child
  getting each signal once.  A child that has not announced itself yet is still importing
  and gets SIGTERM first: a SIGINT there raises KeyboardInterrupt inside an import (a
  traceback).
* Readiness (the same line as printed), each exit and the stop are told to the Notifier
  (cli.system.supervisor.notify: systemd's notify protocol), for whoever started the launch.

Never prints directly: everything goes through the Printer.
"""

from __future__ import annotations

import queue
import signal
import time
from collections.abc import Callable
from typing import Protocol

from turtlectl.cli.system.launchfile import LaunchPlan
from turtlectl.cli.system.supervisor.elsewhere import Elsewhere
from turtlectl.cli.system.supervisor.notify import Notifier
from turtlectl.cli.system.supervisor.printer import Printer
from turtlectl.runtime.client.errors import ExitCode
from turtlectl.runtime.exitcodes import node_exit, respawn_can_help

POLL = 0.05  # s between checks of the children
STABLE_RUN = 10.0  # s: a child that ran this long has its respawn count reset
KILL_WAIT = 1.0  # s for the kernel to reap SIGKILLed children
REAP_POLL = 0.02  # s between checks while children stop


class ChildProcess(Protocol):
    """One node's process, started again on each respawn (cli.system.supervisor.process.Child)."""

    @property
    def pid(self) -> int | None: ...

    def start(self) -> None: ...

    def poll(self) -> int | None:
        """The exit code once it has exited (a signal: minus its number), else None."""

    def running(self) -> bool: ...

    def send(self, sig: signal.Signals) -> None: ...

    def flush_output(self, timeout: float = 1.0) -> None: ...

    #: its output kept off the terminal (its log file only) from its next start on
    quiet: bool

    @property
    def last_line(self) -> str:
        """The last non-blank line of its current start's output ("" for none)."""


def respawn_delay(first: float, cap: float, attempt: int) -> float:
    """Delay (s) before respawn number ``attempt`` (1, 2, …): doubling from ``first``, at most ``cap``."""
    return min(cap, first * 2.0 ** (attempt - 1)) if first > 0 else 0.0


class Supervision:
    """The children of ``plan``, each made once by ``spawn(name)`` and started on demand."""

    def __init__(
        self,
        plan: LaunchPlan,
        printer: Printer,
        spawn: Callable[[str], ChildProcess],
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
        since: float | None = None,
        notifier: Notifier | None = None,
    ):
        """``since``: when the launch began, on ``clock`` (default: now), the start of "ready in".
        ``notifier``: told of readiness, each exit and the stop (default: nobody)."""
        self.entries = {e.name: e for e in plan.launch.node}
        self.programs = set(plan.commands)  # cmd nodes: ready once started
        self.settings = plan.launch.supervisor
        self.printer = printer
        self.notifier = notifier or Notifier()
        self.spawn = spawn
        self.clock = clock
        self.sleep = sleep
        self.children: dict[str, ChildProcess] = {}
        self.stop_reason: str | None = None
        self.exit_code = ExitCode.OK
        self._started_at: dict[str, float] = {}
        self._respawn_at: dict[str, float] = {}
        self._crashes: dict[str, int] = {}  # respawns in a row, per node
        self._start_failures: dict[str, int] = {}  # starts in a row that exited before they were ready
        self._announced: dict[str, int] = {}  # node name -> the pid of its start that announced itself
        self._given_up: set[str] = set()  # nodes that exited for good: no longer watched
        self._lost: dict[str, str] = {}  # given up on after an exit other than 0: how it ended
        self._events: queue.SimpleQueue[tuple[bool, str, int, str]] = queue.SimpleQueue()
        self.elsewhere = Elsewhere()  # the nodes not started here, said as they come, leave, come back
        self._alive: dict[str, int] = {}  # node name -> pid announced
        self._ready_reported = False
        self._t0 = clock() if since is None else since

    # -- input ----------------------------------------------------------------
    def announce(self, alive: bool, name: str, pid: int, host: str = "") -> None:
        """Node ``name`` (process ``pid`` on ``host``) announced itself (``alive``) or went away; any thread."""
        self._events.put((alive, name, pid, host))

    def stop(self, reason: str, code: ExitCode = ExitCode.OK) -> None:
        """Ask the system to stop (the first reason and code win); safe in a signal handler."""
        if self.stop_reason is None:
            self.stop_reason = reason
            self.exit_code = code

    # -- the whole run ----------------------------------------------------------
    def run(self) -> ExitCode:
        """Start every node, watch them until stopped, then stop them all (always)."""
        try:
            self.start_all()
            self.watch()
        finally:
            self.shutdown()
        missing = self.never_started()
        lost = {name: how for name, how in self._lost.items() if name not in missing}
        if (missing or lost) and self.exit_code == ExitCode.OK and self.stop_reason is not None:
            said = [f"{name} {how}" for name, how in missing.items()]
            said += [f"{name} lost: it {how}" for name, how in lost.items()]
            self.stop_reason += "; " + ", ".join(said)
            self.exit_code = ExitCode.FAILED
        return self.exit_code

    def never_started(self) -> dict[str, str]:
        """The nodes whose last start failed before it was ready (given up on, or to be tried
        again), each with "never started" or, if an earlier start of it was ready, "did not
        start again"."""
        return {
            name: "did not start again" if name in self._announced else "never started"
            for name, failures in self._start_failures.items()
            if failures and not self.ready(name)
        }

    def start_all(self) -> None:
        for name in self.entries:
            if self.stop_reason is not None:  # stopped while starting: start no more
                break
            self._start(name)

    def watch(self) -> None:
        while self.stop_reason is None:
            self.step()
            self.sleep(POLL)  # pacing: the supervisor's poll period

    def step(self) -> None:
        """One check of every child: respawns due, exits, readiness."""
        self._drain_events()
        now = self.clock()
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
                if self.stop_reason is not None:
                    return
        if self.stop_reason is None and self._given_up >= set(self.entries):
            # every exit handled and none to be respawned (not merely none running right now:
            # a respawned child that has exited already is respawned again at the next check)
            self.stop("every node has exited", ExitCode.FAILED)

    # -- children -------------------------------------------------------------
    def _start(self, name: str) -> None:
        child = self.children.get(name) or self.children.setdefault(name, self.spawn(name))
        child.quiet = self._start_failures.get(name, 0) > 0  # its traceback was shown once already
        child.start()
        self._started_at[name] = self.clock()
        self.printer.system(f"started {name} (pid {child.pid})")
        if name in self.programs:
            self._check_ready()

    def _exited(self, name: str, child: ChildProcess, code: int, now: float) -> None:
        """Decide what a child's exit means: respawn it (with backoff), or give up on it."""
        child.flush_output()
        entry = self.entries[name]
        how = node_exit(code)
        self.notifier.exited(name, code, how)  # after its output: a listener has its last lines
        if now - self._started_at[name] >= STABLE_RUN:
            self._crashes[name] = 0
        crashes = self._crashes.get(name, 0)
        started = name in self.programs or self._announced.get(name) == child.pid
        failures = 0 if started else self._start_failures.get(name, 0) + 1
        self._start_failures[name] = failures
        hopeless = entry.respawn and not respawn_can_help(code)
        limited = entry.respawn and not started and 0 < entry.start_tries <= failures
        if hopeless:
            how += "; not respawning: respawning cannot help" + self._last_words(name, child, "; last: ")
        elif limited:
            how = (
                f"failed {failures} starts in a row (start_tries = {entry.start_tries}), each exiting before it"
                f" was ready; not respawning it; last: {how}{self._last_words(name, child)}"
            )
        elif entry.respawn and (entry.respawn_max == 0 or crashes < entry.respawn_max):
            self._crashes[name] = crashes + 1
            delay = respawn_delay(entry.respawn_delay, entry.respawn_delay_max, crashes + 1)
            tries = f", start {failures + 1} of {entry.start_tries}" if failures and entry.start_tries else ""
            self.printer.system(f"{name} {how}; respawning in {delay:g} s (respawn {crashes + 1}{tries})")
            self._respawn_at[name] = now + delay
            if not started:
                self._check_ready()  # its next tries do not hold back the others' ready line
            return
        elif not started:
            how += " before it was ready" + self._last_words(name, child)
        self._given_up.add(name)
        if code != 0:  # the system is incomplete without it (a node that ended its work is not lost)
            self._lost[name] = node_exit(code) + (f" after {crashes} respawns" if entry.respawn and crashes else "")
        if entry.respawn and not hopeless and not limited:
            how += f", after {crashes} respawns in a row; giving up on it"
        if entry.required:
            self.printer.system(f"{name} {how}; it is required, stopping the system")
            self.stop(f"required node {name} {how}", ExitCode.FAILED)
        else:
            self.printer.system(f"{name} {how}")
            self._check_ready()  # the others may be all that will be ready

    def _last_words(self, name: str, child: ChildProcess, lead: str = ": ") -> str:
        """A node's last line of output and where its log is, for the line that gives up on it."""
        said = f"{lead}{child.last_line}" if child.last_line else ""
        path = self.printer.log_path(name)
        return said + (f"; full log: {path}" if path is not None else "")

    def _drain_events(self) -> None:
        while True:
            try:
                alive, name, pid, host = self._events.get_nowait()
            except queue.Empty:
                return
            child = self.children.get(name)
            if child is None and name not in self.entries:  # a node this launch does not start
                if (line := self.elsewhere.seen(alive, name, pid, host)) is not None:
                    self.printer.system(line)
                continue
            if child is None or child.pid != pid:
                # not the process started here (another system's node of that name, or an
                # earlier start of this one): it makes nothing ready and unreadies nothing
                if alive and child is not None and child.running():
                    self.printer.system(
                        f"warning: another process (pid {pid}) also calls itself {name}; `turtlectl list` shows both"
                    )
                continue
            if alive:
                self._alive[name] = pid
                self._announced[name] = pid
                failed = self._start_failures.pop(name, 0)
                child.quiet = False
                if failed:
                    self.printer.system(
                        f"{name} ready after {failed} failed start{'s' * (failed != 1)}"
                        f" (its output meanwhile is in its log)"
                    )
            else:
                self._alive.pop(name, None)
            self._check_ready()

    def _check_ready(self) -> None:
        """Say once when every node is ready, or every node that will be: the others given up on
        while starting (an optional node that raised) are named."""
        if self._ready_reported:
            return
        missing = [n for n in self.entries if not self.ready(n)]
        failed = self.never_started()
        if any(n not in self._given_up and n not in failed for n in missing) or len(missing) == len(self.entries):
            return
        self._ready_reported = True
        elapsed = self.clock() - self._t0
        count = len(self.entries)
        since = f"ready in {elapsed:.2f} s (since turtlectl started)"
        if missing:
            why = [f"{n} {failed[n]}" + (f": {last}" if (last := self.children[n].last_line) else "") for n in failed]
            gone = [n for n in missing if n not in failed]
            why += [f"not running: {', '.join(gone)}"] if gone else []
            line = f"{count - len(missing)} of {count} nodes {since}; {'; '.join(why)}"
        else:
            line = f"{'all ' * (count > 1)}{count} node{'s' * (count != 1)} {since}"
        self.printer.system(line)
        self.notifier.ready(line)

    def ready(self, name: str) -> bool:
        """True once this very process of node ``name`` has announced itself (a cmd node: once started)."""
        child = self.children.get(name)
        if name in self.programs:
            return child is not None and child.pid is not None
        return child is not None and child.pid is not None and self._alive.get(name) == child.pid

    # -- stopping ---------------------------------------------------------------
    def shutdown(self) -> None:
        """SIGINT, wait, SIGTERM, wait, SIGKILL: each child gets each signal at most once.

        A child not ready yet is still starting (importing numpy and zenoh), where SIGINT
        would raise KeyboardInterrupt and print a traceback: it gets SIGTERM at the first
        step instead, which ends it silently (the default action) or, once the node runtime
        has installed its handler, stops it as SIGINT does.
        """
        self._drain_events()
        self.notifier.stopping()
        steps = (
            (signal.SIGINT, self.settings.sigint_timeout),
            (signal.SIGTERM, self.settings.sigterm_timeout),
            (signal.SIGKILL, KILL_WAIT),
        )
        sent: dict[str, set[signal.Signals]] = {name: set() for name in self.children}
        for sig, wait in steps:
            targets = [(name, c) for name, c in self.children.items() if c.running()]
            if not targets:
                break
            sends = []
            for name, child in targets:
                first = signal.SIGTERM if sig is signal.SIGINT and not self.ready(name) else sig
                if first not in sent[name]:
                    sends.append((name, child, first))
            escalated = [name for name, _, s in sends if sig is not signal.SIGINT]
            if escalated:
                self.printer.system(f"sending {sig.name} to {', '.join(escalated)}")
            for name, child, first in sends:
                child.send(first)
                sent[name].add(first)
            until = self.clock() + wait
            while self.clock() < until and any(c.running() for _, c in targets):
                self.sleep(REAP_POLL)  # pacing: reaping children
        for child in self.children.values():
            child.flush_output(0.2)
