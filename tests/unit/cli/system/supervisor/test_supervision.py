"""The supervision policy with fake processes and a fake clock: every rule in milliseconds.

Each test scripts a history (when a child exits, when it announces itself, when a stop is
asked for, how it reacts to each signal), runs ``Supervision.run`` on a clock that only
moves when the policy sleeps, and checks what the policy did and when, as honcho tests
its manager with scripted event histories.
"""

from __future__ import annotations

import io
import itertools
import math
import re
import signal
from collections.abc import Callable
from pathlib import Path

import pytest

from turtlectl.cli.system.launchfile import parse_launch
from turtlectl.cli.system.supervisor.printer import Printer
from turtlectl.cli.system.supervisor.supervision import (
    KILL_WAIT,
    POLL,
    REAP_POLL,
    STABLE_RUN,
    Supervision,
    respawn_delay,
)
from turtlectl.runtime.client.errors import ExitCode

INT, TERM, KILL = signal.SIGINT, signal.SIGTERM, signal.SIGKILL
LAG = 2 * POLL + 1e-6  # how late the policy may notice something: it looks every POLL s
REAP = 2 * REAP_POLL + 1e-6  # how late a wait of the shutdown may end: it looks every REAP_POLL s


class Clock:
    """Fake monotonic time: moves only in ``sleep``, firing what was scheduled on the way."""

    def __init__(self) -> None:
        self.now = 0.0
        self._due: list[tuple[float, int, Callable[[], None]]] = []
        self._order = itertools.count()

    def __call__(self) -> float:
        return self.now

    def at(self, when: float, action: Callable[[], None]) -> None:
        self._due.append((when, next(self._order), action))
        self._due.sort(key=lambda item: item[:2])

    def sleep(self, seconds: float) -> None:
        assert seconds > 0
        until = self.now + seconds
        while self._due and self._due[0][0] <= until:
            when, _, action = self._due.pop(0)
            self.now = max(self.now, when)
            action()
        self.now = until
        assert self.now < 3600, "the policy never stopped"


_pids = itertools.count(1000)


class FakeProcess:
    """One node's process, started again on each respawn.

    Start number i runs ``runs[i]`` s (the last one repeats; inf: until signalled) and then
    exits with ``code``; it announces itself ``ready_after`` s after starting (None: never).
    ``stops_on``: the signals it handles, and how long it then takes to exit (code 0);
    SIGKILL always ends it at once (code -9).
    """

    def __init__(
        self,
        name: str,
        system: System,
        runs: tuple[float, ...] = (math.inf,),
        code: int = 1,
        ready_after: float | None = 0.5,
        stops_on: dict[signal.Signals, float] | None = None,
        says: str = "",
    ):
        """``says``: the last line of its output at each start ("" for none)."""
        self.name, self.system, self.runs, self.code, self.ready_after = name, system, runs, code, ready_after
        self.says = says
        self.last_line = ""
        self.quiet = False
        self.quiet_starts: list[bool] = []  # whether each start's output was kept off the terminal
        self.stops_on = {INT: 0.1, TERM: 0.1} if stops_on is None else stops_on
        self.pid: int | None = None
        self.starts: list[float] = []
        self.got: list[tuple[float, signal.Signals]] = []
        self._exit_at = math.inf
        self._exit_code = 0

    def start(self) -> None:
        clock = self.system.clock
        assert not self.running(), f"{self.name} started while still running"
        self.pid = next(_pids)
        self.starts.append(clock.now)
        self.quiet_starts.append(self.quiet)
        self.last_line = self.says
        self._exit_at = clock.now + self.runs[min(len(self.starts), len(self.runs)) - 1]
        self._exit_code = self.code
        if self.ready_after is not None:
            pid = self.pid
            clock.at(clock.now + self.ready_after, lambda: self._announce(pid))

    def _announce(self, pid: int) -> None:
        if pid == self.pid and self.running():
            self.system.supervision.announce(True, self.name, pid)

    def poll(self) -> int | None:
        return self._exit_code if self.pid is not None and self.system.clock.now >= self._exit_at else None

    def running(self) -> bool:
        return self.pid is not None and self.poll() is None

    def send(self, sig: signal.Signals) -> None:
        now = self.system.clock.now
        self.got.append((now, sig))
        if sig is KILL:
            self._exit_at, self._exit_code = now, -int(KILL)
        elif sig in self.stops_on and now + self.stops_on[sig] < self._exit_at:
            self._exit_at, self._exit_code = now + self.stops_on[sig], 0

    def signals(self) -> list[signal.Signals]:
        return [sig for _, sig in self.got]

    def flush_output(self, timeout: float = 1.0) -> None:
        pass


class System:
    """A Supervision of ``nodes`` (launch-file [[node]] tables) on a fake clock."""

    def __init__(
        self,
        nodes: str,
        sigint_timeout: float = 2.0,
        sigterm_timeout: float = 1.0,
        since: float | None = None,
        logs: Path | None = None,
    ):
        text = f"[supervisor]\nsigint_timeout = {sigint_timeout}\nsigterm_timeout = {sigterm_timeout}\n{nodes}"
        plan = parse_launch(text)
        self.clock = Clock()
        self.out = io.StringIO()
        self.processes: dict[str, FakeProcess] = {}
        self.spawned: list[str] = []
        names = [e.name for e in plan.launch.node]
        printer = Printer(names, self.out, colour=False)
        if logs is not None:
            printer.log_to(logs, names)
        self.supervision = Supervision(
            plan, printer, self._spawn, clock=self.clock, sleep=self.clock.sleep, since=since
        )

    def process(self, name: str, **how) -> FakeProcess:
        self.processes[name] = FakeProcess(name, self, **how)
        return self.processes[name]

    def _spawn(self, name: str) -> FakeProcess:
        self.spawned.append(name)
        return self.processes.setdefault(name, FakeProcess(name, self))

    def stop_at(self, when: float, reason: str = "received SIGINT") -> None:
        self.clock.at(when, lambda: self.supervision.stop(reason))

    def run(self) -> ExitCode:
        return self.supervision.run()

    def lines(self) -> list[str]:
        return [line.partition(" | ")[2] for line in self.out.getvalue().splitlines()]


def node(name: str, run: str = "", **keys) -> str:
    """A [[node]] table; ``run`` defaults to ``name`` (a built-in kind)."""
    body = "".join(f"{k} = {str(v).lower() if isinstance(v, bool) else v}\n" for k, v in keys.items())
    return f'[[node]]\nname = "{name}"\nrun = "{run or name}"\n{body}'


def patrol_node(**keys) -> str:
    """A node of the user's, "patrol" (a built-in kind stands in: the policy sees no difference)."""
    return node("patrol", run="status_monitor", **keys)


def gaps(times: list[float]) -> list[float]:
    return [b - a for a, b in itertools.pairwise(times)]


# -- respawn -----------------------------------------------------------------------
def test_respawn_delay_doubles_from_the_first_delay_up_to_the_cap():
    assert [respawn_delay(0.5, 3.0, n) for n in range(1, 6)] == [0.5, 1.0, 2.0, 3.0, 3.0]
    assert respawn_delay(0.0, 30.0, 4) == 0.0


def test_a_crashing_node_is_respawned_after_delays_doubling_up_to_respawn_delay_max():
    system = System(node("sim", respawn=True, respawn_delay=1.0, respawn_delay_max=4.0, respawn_max=0))
    sim = system.process("sim", runs=(0.3,), code=3, ready_after=0.1)  # ready, then it crashes
    system.stop_at(17.0)
    assert system.run() == ExitCode.OK
    assert len(sim.starts) == 6
    for gap, delay in zip(gaps(sim.starts), [1.0, 2.0, 4.0, 4.0, 4.0], strict=True):
        assert delay <= gap - 0.3 <= delay + LAG
    said = [line for line in system.lines() if "respawning" in line]
    assert said[:4] == [
        "sim exited with code 3; respawning in 1 s (respawn 1)",
        "sim exited with code 3; respawning in 2 s (respawn 2)",
        "sim exited with code 3; respawning in 4 s (respawn 3)",
        "sim exited with code 3; respawning in 4 s (respawn 4)",
    ]


@pytest.mark.parametrize("long_run, reset", [(STABLE_RUN, True), (STABLE_RUN - 0.5, False)])
def test_a_run_of_STABLE_RUN_starts_the_respawn_count_and_its_backoff_again(long_run, reset):
    system = System(node("sim", respawn=True, respawn_delay=1.0, respawn_max=3))
    sim = system.process("sim", runs=(0.5, 0.5, long_run, 0.5, 0.5, math.inf), ready_after=0.2)
    system.stop_at(40.0)
    system.run()
    said = [
        re.sub(r"^sim exited with code 1[;,] ", "", line) for line in system.lines() if line.startswith("sim exited")
    ]
    if reset:  # the long run was healthy: count and delay start again, and it never gives up
        assert said == [
            "respawning in 1 s (respawn 1)",
            "respawning in 2 s (respawn 2)",
            "respawning in 1 s (respawn 1)",
            "respawning in 2 s (respawn 2)",
            "respawning in 4 s (respawn 3)",
        ]
        assert len(sim.starts) == 6
    else:  # one run short of healthy: the fourth exit in a row is one too many
        assert said[:3] == [
            "respawning in 1 s (respawn 1)",
            "respawning in 2 s (respawn 2)",
            "respawning in 4 s (respawn 3)",
        ]
        assert said[3] == "after 3 respawns in a row; giving up on it"
        assert len(sim.starts) == 4


def test_a_node_is_given_up_on_after_the_launch_file_s_max_respawns_and_the_rest_runs_on():
    """It was optional: the system runs on and stops only when asked to, then exits FAILED
    naming it (the system was incomplete), as one that never started."""
    system = System(node("sim") + node("status_monitor", respawn=True, respawn_delay=0.2, respawn_max=2))
    sim = system.process("sim")
    monitor = system.process("status_monitor", runs=(0.1,), code=-int(KILL), ready_after=0.05)
    system.stop_at(10.0)
    assert system.run() == ExitCode.FAILED
    assert len(monitor.starts) == 3  # the first run and 2 respawns, then nothing
    assert "status_monitor was killed by SIGKILL, after 2 respawns in a row; giving up on it" in system.lines()
    assert system.supervision.stop_reason == (
        "received SIGINT; status_monitor lost: it was killed by SIGKILL after 2 respawns"
    )
    assert sim.got and sim.got[0][0] == pytest.approx(10.0, abs=LAG)


def test_a_node_without_respawn_that_crashes_after_it_was_ready_leaves_the_system_incomplete():
    system = System(node("sim") + patrol_node())
    system.process("sim")
    system.process("patrol", runs=(1.0,), code=1, ready_after=0.1)
    system.stop_at(3.0)
    assert system.run() == ExitCode.FAILED
    assert system.supervision.stop_reason == "received SIGINT; patrol lost: it exited with code 1"


def test_a_node_that_ends_its_work_with_exit_code_0_is_not_lost():
    system = System(node("sim") + node("setup", run="status_monitor"))
    system.process("sim")
    system.process("setup", runs=(1.0,), code=0, ready_after=0.1)
    system.stop_at(3.0)
    assert system.run() == ExitCode.OK
    assert system.supervision.stop_reason == "received SIGINT"


# -- required ----------------------------------------------------------------------
def test_a_required_node_gone_for_good_stops_the_system_with_exit_code_failed():
    system = System(node("sim", required=True) + node("navigator"))
    system.process("sim", runs=(1.5,), code=2)
    navigator = system.process("navigator")
    assert system.run() == ExitCode.FAILED
    why = "exited with code 2 (bad input: its configuration or its declarations cannot be used)"
    assert system.supervision.stop_reason == f"required node sim {why}"
    assert f"sim {why}; it is required, stopping the system" in system.lines()
    assert navigator.got == [(pytest.approx(1.5, abs=LAG), INT)]  # the others stopped as on Ctrl-C


def test_a_required_node_that_used_up_its_respawns_stops_the_system():
    system = System(node("sim", required=True, respawn=True, respawn_delay=0.2, respawn_max=2) + node("navigator"))
    sim = system.process("sim", runs=(0.3,), code=-int(KILL), ready_after=0.1)
    system.process("navigator")
    assert system.run() == ExitCode.FAILED
    assert len(sim.starts) == 3
    assert system.supervision.stop_reason == (
        "required node sim was killed by SIGKILL, after 2 respawns in a row; giving up on it"
    )


def test_a_system_whose_every_node_has_exited_for_good_stops_with_exit_code_failed():
    system = System(node("sim") + node("navigator"))
    system.process("sim", runs=(1.0,), code=0)
    system.process("navigator", runs=(2.0,), code=1)
    assert system.run() == ExitCode.FAILED
    assert system.supervision.stop_reason == "every node has exited"
    assert system.clock.now == pytest.approx(2.0, abs=LAG)


def test_a_pending_respawn_keeps_the_system_up_while_nothing_runs():
    system = System(node("sim", respawn=True, respawn_delay=3.0))
    sim = system.process("sim", runs=(0.1, math.inf))
    system.stop_at(5.0)
    assert system.run() == ExitCode.OK
    assert len(sim.starts) == 2


# -- starting and readiness -----------------------------------------------------------
def test_a_stop_while_starting_starts_no_more_nodes_and_stops_the_started_ones():
    system = System(node("sim") + node("navigator") + node("status_monitor"))
    sim = system.process("sim")
    navigator = system.process("navigator")
    original = navigator.start

    def start_then_ctrl_c() -> None:
        original()
        system.supervision.stop("received SIGINT")

    navigator.start = start_then_ctrl_c  # type: ignore[method-assign]
    assert system.run() == ExitCode.OK
    assert system.spawned == ["sim", "navigator"]
    assert sim.signals() == [TERM] and navigator.signals() == [TERM]  # neither had announced itself


def test_all_nodes_ready_is_reported_once_when_the_last_one_announces_itself():
    system = System(node("sim") + node("navigator"))
    system.process("sim", ready_after=0.4)
    system.process("navigator", ready_after=1.2)
    system.stop_at(3.0)
    system.run()
    ready = [line for line in system.lines() if "ready in" in line]
    assert len(ready) == 1
    seconds = float(re.fullmatch(r"all 2 nodes ready in (\S+) s \(since turtlectl started\)", ready[0])[1])
    assert 1.2 <= seconds <= 1.2 + LAG


def test_ready_counts_from_when_the_command_began_not_from_the_first_start():
    """The "ready in" time counts everything before the supervision began too (imports, router)."""
    system = System(node("sim"), since=-0.7)
    system.process("sim", ready_after=0.4)
    system.stop_at(2.0)
    system.run()
    ready = [line for line in system.lines() if "ready in" in line]
    seconds = float(re.fullmatch(r"1 node ready in (\S+) s \(since turtlectl started\)", ready[0])[1])
    assert 1.1 <= seconds <= 1.1 + LAG


def test_a_respawned_node_is_ready_only_once_its_new_process_announces_itself():
    system = System(node("sim", respawn=True, respawn_delay=0.2))
    sim = system.process("sim", runs=(1.0, math.inf), ready_after=0.5)
    system.stop_at(1.5)  # the new process started at ~1.2, announces itself at ~1.7
    system.run()
    assert len(sim.starts) == 2 and sim.signals() == [TERM]


# -- shutdown ----------------------------------------------------------------------
def test_shutdown_escalates_sigint_sigterm_sigkill_with_the_launch_file_s_waits_each_signal_once():
    system = System(node("sim") + node("navigator") + node("status_monitor"), sigint_timeout=2.0, sigterm_timeout=1.5)
    polite = system.process("sim", stops_on={INT: 0.3})
    deaf = system.process("navigator", stops_on={TERM: 0.1})
    stuck = system.process("status_monitor", stops_on={})
    system.stop_at(5.0)
    assert system.run() == ExitCode.OK
    assert polite.got == [(pytest.approx(5.0, abs=LAG), INT)]
    t0 = polite.got[0][0]
    assert deaf.got == [(t0, INT), (pytest.approx(t0 + 2.0, abs=REAP), TERM)]
    assert stuck.got == [
        (t0, INT),
        (pytest.approx(t0 + 2.0, abs=REAP), TERM),
        (pytest.approx(t0 + 3.5, abs=REAP), KILL),
    ]
    assert "sending SIGTERM to navigator, status_monitor" in system.lines()
    assert "sending SIGKILL to status_monitor" in system.lines()
    assert system.clock.now <= t0 + 3.5 + KILL_WAIT + LAG


def test_shutdown_waits_only_as_long_as_the_children_take():
    system = System(node("sim") + node("navigator"), sigint_timeout=10.0, sigterm_timeout=10.0)
    system.process("sim", stops_on={INT: 0.2})
    system.process("navigator", stops_on={INT: 0.4})
    system.stop_at(2.0)
    system.run()
    assert system.clock.now == pytest.approx(2.4, abs=LAG + REAP)
    assert not any(line.startswith("sending") for line in system.lines())


def test_a_child_not_yet_ready_gets_sigterm_first_never_a_sigint_inside_its_imports():
    system = System(node("sim") + node("navigator"), sigint_timeout=2.0, sigterm_timeout=1.0)
    ready = system.process("sim", ready_after=0.5, stops_on={})
    importing = system.process("navigator", ready_after=None, stops_on={})
    system.stop_at(3.0)
    system.run()
    t0 = ready.got[0][0]
    assert ready.got == [
        (t0, INT),
        (pytest.approx(t0 + 2.0, abs=REAP), TERM),
        (pytest.approx(t0 + 3.0, abs=REAP), KILL),
    ]
    # SIGTERM at once, not again at the SIGTERM step, then SIGKILL after both waits
    assert importing.got == [(t0, TERM), (pytest.approx(t0 + 3.0, abs=REAP), KILL)]
    assert "sending SIGTERM to sim" in system.lines()


def test_children_are_stopped_even_when_starting_one_fails():
    """No orphans: an error while starting (or watching) still runs the shutdown."""
    system = System(node("sim") + node("navigator"))
    sim = system.process("sim")
    navigator = system.process("navigator")

    def cannot_start() -> None:
        raise OSError("no such interpreter")

    navigator.start = cannot_start  # type: ignore[method-assign]
    with pytest.raises(OSError):
        system.run()
    assert sim.signals() == [TERM]


# -- exits that respawning cannot help -----------------------------------------------
@pytest.mark.parametrize(
    "code, why",
    [
        (2, "exited with code 2 (bad input: its configuration or its declarations cannot be used)"),
        (4, "exited with code 4 (could not start: another process already holds what it claims)"),
    ],
)
def test_a_configuration_error_or_a_conflict_is_given_up_on_at_once_with_one_line_saying_why(code, why):
    system = System(node("sim") + node("navigator", respawn=True, respawn_delay=0.2, respawn_max=0))
    system.process("sim")
    navigator = system.process("navigator", runs=(0.5,), code=code, ready_after=None)
    system.stop_at(10.0)
    assert system.run() == ExitCode.FAILED  # optional: the rest runs on until asked to stop, incomplete
    assert system.supervision.stop_reason == "received SIGINT; navigator never started"
    assert len(navigator.starts) == 1  # never started again, although respawn has no limit
    said = [line for line in system.lines() if line.startswith("navigator ")]
    assert said == [f"navigator {why}; not respawning: respawning cannot help"]


def test_a_required_node_with_a_conflict_stops_the_system_at_once_however_many_respawns_it_has():
    system = System(node("sim", respawn=True, respawn_max=5) + node("navigator", required=True, respawn=True))
    system.process("sim")
    navigator = system.process("navigator", runs=(0.5,), code=4)
    assert system.run() == ExitCode.FAILED
    assert len(navigator.starts) == 1
    assert system.clock.now == pytest.approx(0.5, abs=LAG + 2.0 + REAP)  # no respawn delay waited for
    assert system.supervision.stop_reason.startswith("required node navigator exited with code 4 (could not start")
    assert any(line.endswith("respawning cannot help; it is required, stopping the system") for line in system.lines())


@pytest.mark.parametrize("code", [1, 3, -int(signal.SIGSEGV), -int(KILL), 0])
def test_crashes_and_lost_sessions_are_still_respawned(code):
    system = System(node("sim", respawn=True, respawn_delay=0.2, respawn_max=0))
    sim = system.process("sim", runs=(0.5, math.inf), code=code)
    system.stop_at(3.0)
    assert system.run() == ExitCode.OK
    assert len(sim.starts) == 2
    assert not any("respawning cannot help" in line for line in system.lines())


# -- readiness counts only this supervisor's processes ---------------------------------
def test_another_process_calling_itself_by_a_node_s_name_does_not_make_that_node_ready():
    """A second launch joining a running system: its navigator conflicts with the running one
    (exit 4) and never announces itself; the other system's navigator token (another pid,
    seen at once through the token history) made it "1 node ready"."""
    system = System(node("navigator", respawn=True))
    navigator = system.process("navigator", runs=(0.6,), code=4, ready_after=None)
    other = 4242
    system.supervision.announce(True, "navigator", other)  # the running system's, before ours starts
    system.clock.at(0.3, lambda: system.supervision.announce(True, "navigator", other))
    system.run()
    assert len(navigator.starts) == 1
    assert not any("ready in" in line for line in system.lines())
    assert not system.supervision.ready("navigator")
    assert any(f"another process (pid {other}) also calls itself navigator" in line for line in system.lines())


def test_another_process_going_away_does_not_unready_this_supervisor_s_node():
    system = System(node("sim"))
    sim = system.process("sim", ready_after=0.2)
    system.clock.at(0.5, lambda: system.supervision.announce(True, "sim", 4242))
    system.clock.at(0.7, lambda: system.supervision.announce(False, "sim", 4242))
    seen: list[bool] = []
    system.clock.at(1.0, lambda: seen.append(system.supervision.ready("sim")))
    system.stop_at(1.5)
    system.run()
    assert seen == [True] and sim.signals() == [INT]  # still ready: SIGINT, not SIGTERM


def test_a_cmd_node_is_ready_once_started_and_stopped_with_sigint_as_a_ready_node():
    """A program (cmd) announces nothing: it counts as ready once started."""
    system = System(node("sim") + '[[node]]\nname = "driver"\ncmd = ["sleep", "1000"]\n')
    system.process("sim", ready_after=0.4)
    driver = system.process("driver", ready_after=None, stops_on={INT: 0.1})
    system.stop_at(2.0)
    system.run()
    ready = [line for line in system.lines() if "ready in" in line]
    assert len(ready) == 1 and ready[0].startswith("all 2 nodes ready in 0.4")
    assert driver.signals() == [INT]


def test_a_system_of_cmd_nodes_only_is_ready_once_they_are_started():
    system = System('[[node]]\nname = "driver"\ncmd = ["sleep", "1000"]\n')
    system.process("driver", ready_after=None)
    system.stop_at(1.0)
    system.run()
    assert [line for line in system.lines() if "ready in" in line] == [
        "1 node ready in 0.00 s (since turtlectl started)"
    ]


def test_when_an_optional_node_dies_while_starting_the_rest_is_reported_ready_with_who_is_missing():
    """`broken` raises in its constructor: the launch still says which of the other nodes are
    ready and which never started (one line; not only 'all N ready')."""
    system = System(node("sim") + node("navigator") + '[[node]]\nname = "broken"\nrun = "status_monitor"\n')
    system.process("sim", ready_after=0.4)
    system.process("navigator", ready_after=0.8)
    system.process("broken", runs=(0.2,), code=1)
    system.stop_at(3.0)
    system.run()
    ready = [line for line in system.lines() if "ready in" in line]
    assert len(ready) == 1, system.lines()
    match = re.fullmatch(r"2 of 3 nodes ready in (\S+) s \(since turtlectl started\); broken never started", ready[0])
    assert match and 0.8 <= float(match[1]) <= 0.8 + LAG, ready


# -- start failures: a start limit, as systemd's --------------------------------------
BOOM = "RuntimeError: the patrol cannot start"


def test_a_node_that_fails_while_starting_start_tries_times_in_a_row_is_not_respawned(tmp_path):
    """A constructor that always raises was respawned 1+2+4+8+16 s (respawn_max), its traceback
    printed at every start, and nothing said why it never came up."""
    system = System(
        node("sim") + patrol_node(respawn=True, respawn_delay=0.2, respawn_max=0, start_tries=3), logs=tmp_path
    )
    system.process("sim", ready_after=0.1)
    patrol = system.process("patrol", runs=(0.3,), code=1, ready_after=None, says=BOOM)
    system.stop_at(20.0)
    system.run()
    assert len(patrol.starts) == 3  # then never again, although respawn_max has no limit
    assert [line for line in system.lines() if "respawning in" in line] == [
        "patrol exited with code 1; respawning in 0.2 s (respawn 1, start 2 of 3)",
        "patrol exited with code 1; respawning in 0.4 s (respawn 2, start 3 of 3)",
    ]
    assert patrol.quiet_starts == [False, True, True]  # its output (the traceback) on the terminal once
    given_up = [line for line in system.lines() if "not respawning" in line]
    assert given_up == [
        f"patrol failed 3 starts in a row (start_tries = 3), each exiting before it was ready; not respawning it; "
        f"last: exited with code 1: {BOOM}; full log: {tmp_path / 'patrol.log'}"
    ]


def test_the_ready_line_names_a_node_that_never_started_without_waiting_out_its_backoff():
    system = System(node("sim") + node("navigator") + patrol_node(respawn=True, respawn_delay=30.0))
    system.process("sim", ready_after=0.4)
    system.process("navigator", ready_after=0.6)
    system.process("patrol", runs=(0.3,), code=1, ready_after=None, says=BOOM)
    system.stop_at(5.0)
    system.run()
    ready = [line for line in system.lines() if "ready in" in line]
    assert len(ready) == 1, system.lines()
    match = re.fullmatch(
        rf"2 of 3 nodes ready in (\S+) s \(since turtlectl started\); patrol never started: {BOOM}", ready[0]
    )
    assert match and 0.6 <= float(match[1]) <= 0.6 + LAG, ready


def test_a_stop_with_a_node_that_never_started_exits_failed_and_says_which():
    system = System(node("sim") + patrol_node(respawn=True, respawn_delay=0.2, start_tries=2))
    system.process("sim")
    system.process("patrol", runs=(0.3,), code=1, ready_after=None, says=BOOM)
    system.stop_at(5.0)
    assert system.run() == ExitCode.FAILED
    assert system.supervision.stop_reason == "received SIGINT; patrol never started"


def test_a_stop_while_a_node_is_still_being_retried_also_says_it_never_started():
    system = System(node("sim") + patrol_node(respawn=True, respawn_delay=10.0))
    system.process("sim")
    system.process("patrol", runs=(0.3,), code=1, ready_after=None)
    system.stop_at(2.0)
    assert system.run() == ExitCode.FAILED
    assert system.supervision.stop_reason == "received SIGINT; patrol never started"


def test_a_stop_before_a_node_had_time_to_start_is_not_a_failure():
    system = System(node("sim") + patrol_node())
    system.process("sim")
    system.process("patrol", ready_after=None)  # still importing when Ctrl-C comes
    system.stop_at(0.3)
    assert system.run() == ExitCode.OK


def test_a_node_that_starts_at_its_second_try_counts_as_started_and_speaks_again():
    system = System(node("sim") + patrol_node(respawn=True, respawn_delay=0.2, start_tries=3))
    system.process("sim")
    patrol = system.process("patrol", runs=(0.3, math.inf), code=1, ready_after=0.5, says=BOOM)
    seen: list[bool] = []
    system.clock.at(3.0, lambda: seen.append(patrol.quiet))
    system.stop_at(4.0)
    assert system.run() == ExitCode.OK
    assert len(patrol.starts) == 2 and patrol.quiet_starts == [False, True] and seen == [False]
    assert "patrol ready after 1 failed start (its output meanwhile is in its log)" in system.lines()


def test_start_failures_count_in_a_row_a_ready_start_begins_the_count_again():
    """Crashes after it was ready are respawned by respawn_max's rule, not the start limit."""
    system = System(patrol_node(respawn=True, respawn_delay=0.2, respawn_max=0, start_tries=2) + node("sim"))
    system.process("sim")
    # fails to start, then starts and crashes later, then fails to start, then runs
    patrol = system.process("patrol", runs=(0.2, 1.0, 0.2, math.inf), code=1, ready_after=0.5)
    system.stop_at(10.0)
    assert system.run() == ExitCode.OK
    assert len(patrol.starts) == 4
    assert not any("not respawning" in line for line in system.lines())


def test_a_required_node_that_never_starts_stops_the_system_at_its_start_limit():
    """required means: when it exits for good the system stops (exit 1); a start limit reached
    is such an exit."""
    system = System(node("sim") + patrol_node(required=True, respawn=True, respawn_delay=0.2, start_tries=2))
    system.process("sim")
    patrol = system.process("patrol", runs=(0.3,), code=1, ready_after=None, says=BOOM)
    assert system.run() == ExitCode.FAILED
    assert len(patrol.starts) == 2
    assert system.supervision.stop_reason.startswith("required node patrol failed 2 starts in a row")
    assert any(line.endswith(f"{BOOM}; it is required, stopping the system") for line in system.lines())


def test_a_node_without_respawn_that_fails_while_starting_says_its_last_error_and_log(tmp_path):
    system = System(node("sim") + patrol_node(), logs=tmp_path)
    system.process("sim")
    system.process("patrol", runs=(0.3,), code=1, ready_after=None, says=BOOM)
    system.stop_at(2.0)
    assert system.run() == ExitCode.FAILED
    said = [line for line in system.lines() if line.startswith("patrol ")]
    assert said == [f"patrol exited with code 1 before it was ready: {BOOM}; full log: {tmp_path / 'patrol.log'}"]
