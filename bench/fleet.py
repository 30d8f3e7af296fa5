"""Benchmark of many turtles: the whole system with N turtles, each
with its own navigator, status monitor and obstacle detector (turtle1's outside a namespace,
turtle2..N in [[group]]s), next to the raw zenoh-python floor of the same traffic in the same run.

Per N (default 1, 2, 5, 10): a launch file is written to a temporary folder (the turtles on a grid
in the 11.09 m world without obstacles, 2 m or more apart), launched with the tests' System, and
measured:

- idle CPU (% of one core) and PSS of every process of the system (supervisor with the router,
  zygote, nodes), in total and per turtle; CPU as the median of 4 windows (2 s each);
- the raw floor: per turtle one 62.5 Hz publisher and three callback subscribers of it (the sim's
  pose to the turtle's three nodes), bench/raw_pub.py, all N sets together, measured the same way
  after the system is stopped, through a bare `turtlectl router` (so neither disturbs the other on
  the 2 cores); the ratio of the system's CPU to it (target <= 1.25x);
- the status period of every turtle at once (`robot/status`, `turtle2/robot/status`, ...):
  |period - 100 ms| at the publisher (TurtleStatus stamps) p99 and at a subscriber (arrival) max
  (the first 5 statuses of the new subscription dropped: they come bunched);
- goals for all turtles at once (threads, one turtlectl.Client each): each drives 2.5 m along its
  own lane (+y, then back, then +y again: rounds), success rate and mean time_taken against
  turtle1 alone doing the same goals in the N=1 run.

Usage: .venv/bin/python bench/fleet.py [--turtles 1,2,5,10] [--quick]
"""

from __future__ import annotations

import argparse
import math
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import psutil
import zenoh

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

import tests.integration.harness as harness  # noqa: E402  (the same launcher as the tests)
from tests.integration.harness import System, session_members  # noqa: E402
from turtlectl import Client, Error  # noqa: E402
from turtlectl.messages import TurtleStatus, decode  # noqa: E402
from turtlectl.messages.keys import STATUS, resolve  # noqa: E402
from turtlectl.runtime.session import close_session, peer_config  # noqa: E402

try:
    from system import machine, pct  # bench/system.py's
except ImportError:  # pragma: no cover - a copy, should bench/system.py move

    def pct(values: list[float], q: float) -> float:
        ordered = sorted(values) or [math.nan]
        return ordered[min(len(ordered) - 1, int(round(q / 100 * (len(ordered) - 1))))]

    def machine() -> str:
        import platform

        return f"{platform.processor()}, {psutil.cpu_count()} cores; Python {platform.python_version()}"


RAW = [sys.executable, str(ROOT / "bench" / "raw_pub.py")]
PORTS = range(7700, 7800)  # the ports this benchmark may use
WORLD = 11.088889  # m
LANE = 2.5  # m each goal drives
KINDS = ("navigator", "status_monitor", "obstacle_detector")


def port_in_range() -> int:
    """A free port among PORTS (the tests' System picks any free port; this bench keeps to its own)."""
    for port in PORTS:
        with socket.socket() as s:
            try:
                s.bind(("127.0.0.1", port))
            except OSError:
                continue
            return port
    raise RuntimeError(f"no free port in {PORTS.start}-{PORTS.stop - 1}")


harness.free_port = port_in_range  # System() calls harness.free_port


def names(n: int) -> list[str]:
    return [f"turtle{i + 1}" for i in range(n)]


def spawn(i: int) -> tuple[float, float]:
    """Turtle i's start: 5 lanes 2 m apart (x 1.5 to 9.5 m), two rows (y 1.5 and 6.5 m); each
    goal runs 2.5 m up its lane, so no two paths cross and turtles stay >= 2 m apart."""
    if i >= 10:
        raise ValueError("the grid holds 10 turtles")
    return 1.5 + 2.0 * (i % 5), 1.5 + 5.0 * (i // 5)


def launch_file(n: int) -> str:
    """N turtles, each with its three nodes; no obstacles."""
    x1, y1 = spawn(0)
    others = ",\n".join(
        f'  {{ name = "{name}", x = {spawn(i)[0]}, y = {spawn(i)[1]}, theta = {math.pi / 2:.6f} }}'
        for i, name in enumerate(names(n))
        if i > 0
    )
    out = [
        f"# bench/fleet.py: {n} turtle(s), each with a navigator, status monitor and obstacle detector",
        "[world]",
        f"size = {WORLD}",
        "obstacles = []",
        "",
        "[[node]]",
        'name = "sim"',
        'run = "sim"',
        "required = true",
        "[node.params]",
        f"x = {x1}",
        f"y = {y1}",
        f"theta = {math.pi / 2:.6f}",
        f"turtles = [\n{others}\n]" if others else "turtles = []",
    ]
    for kind in KINDS:
        out += ["", "[[node]]", f'name = "{kind}"', f'run = "{kind}"', "respawn = true"]
    for name in names(n)[1:]:
        out += ["", "[[group]]", f'namespace = "{name}"']
        for kind in KINDS:
            out += ["[[group.node]]", f'name = "{kind}"', f'run = "{kind}"', "respawn = true"]
    return "\n".join(out) + "\n"


def node_names(n: int) -> tuple[str, ...]:
    return ("sim", *KINDS, *(f"{name}/{kind}" for name in names(n)[1:] for kind in KINDS))


def namespace(name: str) -> str:
    return "" if name == "turtle1" else name


# -- CPU and memory ----------------------------------------------------------------------------


def system_processes(system: System) -> dict[int, str]:
    """pid -> what it is, for every live process of the system's session (supervisor, zygote, nodes)."""
    by_pid = {pid: name for name, pid in system.alive.items()}
    out = {}
    for pid in session_members(system.proc.pid):
        if pid == system.proc.pid:
            out[pid] = "launch (router)"
        elif pid in by_pid:
            out[pid] = by_pid[pid].split("/")[-1]
        else:
            try:
                out[pid] = psutil.Process(pid).name()
            except psutil.Error:
                continue
    return out


def cpu_windows(pids: list[int], windows: int, seconds: float) -> list[dict[int, float]]:
    """CPU % of one core per process over ``windows`` consecutive windows of ``seconds``."""
    procs = {}
    for pid in pids:
        try:
            procs[pid] = psutil.Process(pid)
            procs[pid].cpu_percent(None)
        except psutil.Error:
            pass
    out = []
    for _ in range(windows):
        time.sleep(seconds)  # pacing: one measured window
        row = {}
        for pid, p in procs.items():
            try:
                row[pid] = p.cpu_percent(None)
            except psutil.Error:
                row[pid] = math.nan
        out.append(row)
    return out


def memory(pids: list[int]) -> tuple[float, str]:
    """PSS (shared pages counted once) of the processes, MiB; RSS if PSS cannot be read."""
    try:
        return sum(psutil.Process(p).memory_full_info().pss for p in pids) / 2**20, "PSS"
    except (psutil.Error, AttributeError):
        return sum(psutil.Process(p).memory_info().rss for p in pids) / 2**20, "RSS"


def raw_floor(n: int, windows: int, seconds: float) -> tuple[list[float], float]:
    """The floor of N turtles' pose traffic in raw zenoh-python, through a bare router: per turtle a
    62.5 Hz publisher and three callback subscribers of it, all together.  (total CPU % per
    window, the router's median CPU %)."""
    port = port_in_range()
    endpoint = f"tcp/127.0.0.1:{port}"
    router = subprocess.Popen(
        [*harness.turtlectl(), "router", "--port", str(port)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    procs: list[subprocess.Popen] = []
    try:
        assert router.stdout is not None
        line = router.stdout.readline()  # an event: the router says it listens
        assert "router listening" in line, line
        count = 4 * n
        warmup = 2.0 + 0.4 * count  # the processes import zenoh and open their sessions on 2 cores
        duration = str(warmup + windows * seconds + 10.0)
        for i in range(n):
            key = f"bench/floor/{i}"
            procs.append(subprocess.Popen([*RAW, "pub", endpoint, key, "62.5", duration]))
            procs += [subprocess.Popen([*RAW, "sub", endpoint, key, duration]) for _ in range(3)]
        time.sleep(warmup)  # pacing: until every raw process is up and settled
        rows = cpu_windows([p.pid for p in procs] + [router.pid], windows, seconds)
        totals = [sum(v for pid, v in row.items() if pid != router.pid) for row in rows]
        return totals, statistics.median(row[router.pid] for row in rows)
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            try:
                p.wait(10)
            except subprocess.TimeoutExpired:
                p.kill()
        router.terminate()
        try:
            router.wait(10)
        except subprocess.TimeoutExpired:
            router.kill()


# -- status period -------------------------------------------------------------------------------


@dataclass
class StatusStream:
    arrivals: list[float] = field(default_factory=list)
    stamps: list[int] = field(default_factory=list)


SETTLE = 5  # statuses dropped after subscribing: the first 2-3 of a new subscription arrive bunched (0 ms apart)


def status_periods(endpoint: str, turtles: list[str], count: int, timeout: float) -> dict[str, StatusStream]:
    """``count`` + 1 statuses of every turtle, all subscribed at once from one peer session, after
    the first SETTLE of each (at N=10 the first 2-3 after a subscription arrive together, their stamps
    100 ms apart: a transient of the new subscription, not the stream's period)."""
    streams = {name: StatusStream() for name in turtles}
    lock = threading.Lock()
    session = zenoh.open(peer_config(endpoint))
    subs = []
    try:
        for name in turtles:

            def on(sample: zenoh.Sample, s: StatusStream = streams[name]) -> None:
                now = time.monotonic()
                stamp = decode(sample.payload.to_bytes(), TurtleStatus).stamp
                with lock:
                    s.arrivals.append(now)
                    s.stamps.append(stamp)

            subs.append(session.declare_subscriber(resolve(STATUS, namespace(name)), on))
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with lock:
                if all(len(s.arrivals) > count + SETTLE for s in streams.values()):
                    break
            time.sleep(0.1)  # pacing: waiting for the samples
        for sub in subs:
            sub.undeclare()
    finally:
        close_session(session)
    for s in streams.values():
        del s.arrivals[:SETTLE], s.stamps[:SETTLE]
    return streams


def deviations(values: list[float], count: int) -> list[float]:
    v = values[: count + 1]
    return [abs((b - a) - 0.1) for a, b in zip(v, v[1:], strict=False)]


# -- goals ---------------------------------------------------------------------------------------


def goal_rounds(quick: bool) -> list[tuple[float, float]]:
    """(dy from the spawn, heading in degrees) of each round: up the lane, back, up again."""
    rounds = [(LANE, 90.0), (0.0, -90.0), (LANE, 90.0)]
    return rounds[:2] if quick else rounds


def run_goals(
    endpoint: str, turtles: list[str], rounds: list[tuple[float, float]]
) -> list[dict[str, tuple[bool, float, str]]]:
    """Every turtle's goal of each round at once; per round: turtle -> (success, time_taken s, why not)."""
    clients = {name: Client(endpoint, turtle="" if name == "turtle1" else name) for name in turtles}
    out = []
    try:
        for dy, heading in rounds:
            results: dict[str, tuple[bool, float, str]] = {}
            barrier = threading.Barrier(len(turtles))

            def one(
                i: int,
                name: str,
                dy: float = dy,
                heading: float = heading,
                barrier: threading.Barrier = barrier,
                results: dict[str, tuple[bool, float, str]] = results,
            ) -> None:
                x, y = spawn(i)
                barrier.wait()
                try:
                    response = clients[name].goto(x, y + dy, heading, timeout=60.0)
                    results[name] = (response.success, response.time_taken, "" if response.success else response.reason)
                except Error as exc:
                    results[name] = (False, math.nan, f"{type(exc).__name__}: {exc}")

            threads = [threading.Thread(target=one, args=(i, name)) for i, name in enumerate(turtles)]
            for t in threads:
                t.start()
            for t in threads:
                t.join(90.0)
            out.append(results)
    finally:
        for c in clients.values():
            c.close()
    return out


# -- one N ---------------------------------------------------------------------------------------


@dataclass
class Row:
    n: int
    processes: int = 0
    cpu: list[float] = field(default_factory=list)
    by_kind: dict[str, float] = field(default_factory=dict)
    floor: list[float] = field(default_factory=list)
    floor_router: float = math.nan
    mem: float = math.nan
    mem_kind: str = "PSS"
    pub_p99: dict[str, float] = field(default_factory=dict)
    sub_max: dict[str, float] = field(default_factory=dict)
    mean_period: dict[str, float] = field(default_factory=dict)
    goals: list[dict[str, tuple[bool, float, str]]] = field(default_factory=list)
    ready_s: float = math.nan
    goal_cpu: float = math.nan
    goal_wall: float = math.nan
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def measure(n: int, args: argparse.Namespace, folder: Path) -> Row:
    row = Row(n)
    path = folder / f"fleet{n}.toml"
    path.write_text(launch_file(n))
    turtles = names(n)
    started = time.monotonic()
    system = System(path)
    try:
        system.wait_ready(node_names(n), timeout=180)
        row.ready_s = time.monotonic() - started
        # the data path: every turtle's status has flowed
        first = status_periods(system.endpoint, turtles, 1, timeout=30)
        missing = [t for t, s in first.items() if not s.arrivals]
        assert not missing, f"no status from {missing}"
        time.sleep(args.warmup)  # pacing: the system settles after start before the idle window
        procs = system_processes(system)
        row.processes = len(procs)
        rows = cpu_windows(list(procs), args.windows, args.window)
        row.cpu = [sum(v for v in r.values() if not math.isnan(v)) for r in rows]
        for pid, what in procs.items():
            row.by_kind[what] = row.by_kind.get(what, 0.0) + statistics.median(r.get(pid, math.nan) for r in rows)
        row.mem, row.mem_kind = memory(list(procs))
        streams = status_periods(system.endpoint, turtles, args.periods, timeout=(args.periods + SETTLE) / 10 + 30)
        for name, s in streams.items():
            row.pub_p99[name] = pct(deviations([t / 1e9 for t in s.stamps], args.periods), 99)
            row.sub_max[name] = max(deviations(s.arrivals, args.periods), default=math.nan)
            a = s.arrivals[: args.periods + 1]
            row.mean_period[name] = (a[-1] - a[0]) / (len(a) - 1) if len(a) > 1 else math.nan
        busy = {}
        for pid in procs:
            try:
                busy[pid] = psutil.Process(pid)
                busy[pid].cpu_percent(None)
            except psutil.Error:
                pass
        goals_started = time.monotonic()
        row.goals = run_goals(system.endpoint, turtles, goal_rounds(args.quick))
        row.goal_wall = time.monotonic() - goals_started
        row.goal_cpu = sum(p.cpu_percent(None) for p in busy.values() if p.is_running())
        system.check_alive()
        row.errors = [line for line in system.lines if "ERROR" in line or "Traceback" in line]
        row.warnings = [line for line in system.lines if "WARNING" in line]
    finally:
        try:
            system.stop()
        except AssertionError as exc:
            print(f"N={n}: {exc}".splitlines()[0])
        system.kill_everything()
    row.floor, row.floor_router = raw_floor(n, args.windows, args.window)
    return row


def show_row(row: Row, reference: list[float] | None) -> str:
    n = row.n
    cpu, floor = statistics.median(row.cpu), statistics.median(row.floor)
    results = [r for rnd in row.goals for r in rnd.values()]
    ok = sum(1 for s, _, _ in results if s)
    if reference:
        ratios = []
        for k, rnd in enumerate(row.goals):
            taken = [t for s, t, _ in rnd.values() if s]
            if taken and k < len(reference) and not math.isnan(reference[k]):
                ratios.append(statistics.mean(taken) / reference[k])
        ratio = f"{statistics.mean(ratios):.2f}x" if ratios else "n/a"
    else:
        ratio = "n/a (no N=1 run)"
    pub = max(row.pub_p99.values()) * 1e3
    sub = max(row.sub_max.values()) * 1e3
    sub_med = statistics.median(row.sub_max.values()) * 1e3
    period = statistics.median(row.mean_period.values()) * 1e3
    return (
        f"| {n} | {row.processes} | {cpu:.1f} % ({min(row.cpu):.1f}–{max(row.cpu):.1f}) | {cpu / n:.1f} % | "
        f"{floor:.1f} % ({floor / n:.1f} % per turtle) | {cpu / max(floor, 0.1):.2f}x | "
        f"{row.mem:.0f} MiB | {row.mem / n:.0f} MiB | {pub:.2f} ms | {sub_med:.1f} / {sub:.1f} ms | {period:.2f} ms | "
        f"{ok}/{len(results)} | {ratio} |"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--turtles", default="1,2,5,10", help="the Ns, comma-separated (at most 10)")
    ap.add_argument("--quick", action="store_true", help="a smoke run: N=1,2, short windows, 2 goal rounds")
    args = ap.parse_args()
    ns = [1, 2] if args.quick else sorted({int(x) for x in args.turtles.split(",")})
    args.windows, args.window = (2, 1.5) if args.quick else (4, 2.0)
    args.warmup = 2.0 if args.quick else 5.0
    args.periods = 20 if args.quick else 50

    print(f"machine: {machine()}")
    print(f"load average at start: {' '.join(f'{x:.2f}' for x in psutil.getloadavg())}")
    print(
        f"N turtles, each: navigator, status_monitor, obstacle_detector (turtle1's outside a namespace); "
        f"idle CPU: median of {args.windows} windows of {args.window:g} s after {args.warmup:g} s; status: "
        f"{args.periods} periods per turtle, all at once; goals: {len(goal_rounds(args.quick))} rounds of "
        f"{LANE} m each, all turtles at once"
    )
    rows: list[Row] = []
    with tempfile.TemporaryDirectory(prefix="turtlectl-fleet-") as tmp:
        for n in ns:
            load = psutil.getloadavg()[0]
            row = measure(n, args, Path(tmp))
            rows.append(row)
            cpu = statistics.median(row.cpu)
            print(
                f"\nN={n}: ready in {row.ready_s:.1f} s, {row.processes} processes; 1-min load average "
                f"{load:.2f} before, {psutil.getloadavg()[0]:.2f} after (the raw floor's 4N starts included)"
            )
            print(
                f"  idle CPU per window {', '.join(f'{c:.1f}' for c in row.cpu)} %; by kind (median, summed): "
                + ", ".join(f"{k} {v:.1f}" for k, v in sorted(row.by_kind.items(), key=lambda kv: -kv[1]))
            )
            print(
                f"  raw floor per window {', '.join(f'{c:.1f}' for c in row.floor)} % "
                f"({4 * n} raw processes; the bare router beside them {row.floor_router:.1f} %, not counted)"
            )
            print(
                f"  {row.mem_kind} {row.mem:.0f} MiB; ratio CPU/floor {cpu / max(statistics.median(row.floor), 0.1):.2f}x"
            )
            for name in names(n):
                print(
                    f"  {name}: status |period-100ms| publisher p99 {row.pub_p99[name] * 1e3:.2f} ms, "
                    f"subscriber max {row.sub_max[name] * 1e3:.1f} ms, mean period {row.mean_period[name] * 1e3:.2f} ms"
                )
            for k, rnd in enumerate(row.goals):
                taken = [t for s, t, _ in rnd.values() if s]
                failed = {name: why for name, (s, _, why) in rnd.items() if not s}
                print(
                    f"  goal round {k + 1}: {len(taken)}/{n} reached, time_taken "
                    + (f"mean {statistics.mean(taken):.3f} s, max {max(taken):.3f} s" if taken else "-")
                    + (f"; failed: {failed}" if failed else "")
                )
            print(
                f"  CPU of the whole system while the goals ran ({row.goal_wall:.1f} s): {row.goal_cpu:.1f} % of one core"
            )
            if row.errors:
                print(f"  {len(row.errors)} ERROR/Traceback lines in the system's output, e.g.: {row.errors[0]}")
            for line in row.warnings[:10]:
                print(f"  system output: {line}")

    reference = None
    one = next((r for r in rows if r.n == 1), None)
    if one is not None:
        reference = [
            rnd.get("turtle1", (False, math.nan, ""))[1] if rnd.get("turtle1", (False,))[0] else math.nan
            for rnd in one.goals
        ]
    print()
    print(
        "| N | processes | idle CPU, whole system (median, range) | per turtle | raw floor, same run | ratio (target ≤ 1.25x) "
        f"| {rows[0].mem_kind} | per turtle | status publisher p99 (worst turtle) | status subscriber max (median / worst turtle) "
        "| mean status period | goals reached | time_taken vs turtle1 alone |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for row in rows:
        print(show_row(row, reference))
    if len(rows) > 1:
        a, b = rows[0], rows[-1]
        print(
            f"\nmarginal cost of a turtle (N={a.n} -> N={b.n}): CPU "
            f"{(statistics.median(b.cpu) - statistics.median(a.cpu)) / (b.n - a.n):.1f} %, "
            f"{b.mem_kind} {(b.mem - a.mem) / (b.n - a.n):.0f} MiB"
        )


if __name__ == "__main__":
    main()
