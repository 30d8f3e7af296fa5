"""Benchmark of the whole system, measured side by side with raw baselines in one run.

Reports: launch-to-ready time next to a bare interpreter importing the same libraries;
`turtlectl --help` next to importing typer; `turtlectl echo robot/status --once` next
to a raw zenoh-python client; status period at the publisher (stamps) and at a
subscriber; goal time as the client sees it vs the navigator's time_taken; one-way
latency of robot/status next to raw zenoh-python pub/sub in the same topology; CPU and
memory per process, idle and navigating, next to a raw 62.5 Hz publisher, a raw 62.5 Hz
callback subscriber and an idle session; with --minutes N, a soak that sends goals back
to back for N minutes and counts errors and memory growth.  Ends with the table of
the targets: each figure, its baseline, the ratio and the target.

Usage: python bench/system.py [--minutes N] [--launches N] [--periods N] [--goals N]
       python bench/system.py --before DIR [--rounds N] [--no-zygote]  (bench/versus.py: this
       checkout against the code before, alternated, on launch-to-ready, --help, idle CPU and
       memory, status latency)
"""

from __future__ import annotations

import argparse
import math
import platform
import random
import statistics
import struct
import subprocess
import sys
import time
from importlib import metadata
from pathlib import Path

import psutil
import zenoh

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.integration.harness import NODES, System  # noqa: E402  (the same launcher as the tests)
from turtlectl.cli.system.launchfile import load_launch  # noqa: E402
from turtlectl.messages import NavigateToResponse, Reset, TurtleStatus, decode  # noqa: E402
from turtlectl.messages.keys import POSE, RESET, STATUS  # noqa: E402
from turtlectl.runtime.session import close_session, peer_config  # noqa: E402


def pct(values: list[float], q: float) -> float:
    ordered = sorted(values) or [math.nan]
    return ordered[min(len(ordered) - 1, int(round(q / 100 * (len(ordered) - 1))))]


def summary(values: list[float], unit: str, scale: float = 1.0) -> str:
    v = [x * scale for x in values]
    return f"n={len(v)} p50={pct(v, 50):.3f} p95={pct(v, 95):.3f} p99={pct(v, 99):.3f} max={max(v):.3f} {unit}"


def machine() -> str:
    cpu = platform.processor() or "unknown cpu"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = psutil.virtual_memory().total / 2**30
    return (
        f"{cpu}, {psutil.cpu_count()} cores, {mem:.0f} GiB; Linux {platform.release()}; "
        f"Python {platform.python_version()}; eclipse-zenoh {metadata.version('eclipse-zenoh')}; "
        f"writing bytecode {'off (PYTHONDONTWRITEBYTECODE): make bytecode compiled ours' if sys.flags.dont_write_bytecode else 'on'}"
    )


def launch_to_ready(launches: int) -> list[float]:
    times = []
    for _ in range(launches):
        started = time.monotonic()
        system = System()
        try:
            system.wait_ready(NODES, timeout=30)
            times.append(time.monotonic() - started)
        finally:
            system.stop()
            system.kill_everything()
    return times


class Stamped:
    """A peer subscriber that records (arrival monotonic s, one-way latency s) and the stamps (ns)."""

    def __init__(self, session: zenoh.Session, key: str, stamp_of):
        self.samples: list[tuple[float, float]] = []
        self.stamps: list[int] = []
        self._stamp_of = stamp_of
        self._sub = session.declare_subscriber(key, self._on)

    def _on(self, sample: zenoh.Sample) -> None:
        now_wall, now = time.time_ns(), time.monotonic()
        stamp = self._stamp_of(sample.payload.to_bytes())
        self.stamps.append(stamp)
        self.samples.append((now, (now_wall - stamp) / 1e9))

    def close(self) -> None:
        self._sub.undeclare()


def wall(argv: list[str], runs: int) -> list[float]:
    """Wall time (s) of ``argv`` run to its end, ``runs`` times."""
    times = []
    for _ in range(runs):
        started = time.monotonic()
        subprocess.run(argv, capture_output=True, timeout=60, check=False)
        times.append(time.monotonic() - started)
    return times


RAW = [sys.executable, str(ROOT / "bench" / "raw_pub.py")]


def raw_cpu(args: list[str], warmup: float = 1.5, window: float = 5.0) -> tuple[float, float]:
    """CPU % of one core and RSS MiB of a raw zenoh-python process (bench/raw_pub.py ``args``)."""
    proc = subprocess.Popen([*RAW, *args])
    try:
        time.sleep(warmup)  # pacing: the process imports, opens its session and settles
        ps = psutil.Process(proc.pid)
        ps.cpu_percent(None)
        time.sleep(window)  # pacing: the measured window
        return ps.cpu_percent(None), ps.memory_info().rss / 2**20
    finally:
        proc.terminate()
        proc.wait(10)


def raw_group_cpu(groups: list[list[str]], warmup: float = 1.5, window: float = 5.0) -> list[float]:
    """CPU % of one core of raw zenoh-python processes running together (bench/raw_pub.py args each)."""
    procs = [subprocess.Popen([*RAW, *args]) for args in groups]
    try:
        time.sleep(warmup)  # pacing: the processes import, open their sessions and settle
        ps = [psutil.Process(p.pid) for p in procs]
        for p in ps:
            p.cpu_percent(None)
        time.sleep(window)  # pacing: the measured window
        return [p.cpu_percent(None) for p in ps]
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            p.wait(10)


def goal(system: System, x: float, y: float, theta: float) -> tuple[NavigateToResponse | None, float]:
    try:
        response, elapsed, _ = system.navigate(x, y, theta, timeout=40.0)
    except AssertionError as exc:  # an error reply: counted as a failure
        print(f"goal ({x:.2f}, {y:.2f}, {theta:.0f}) failed: {exc}")
        return None, 0.0
    return response, elapsed


def random_goal(rng: random.Random, system: System) -> tuple[float, float, float]:
    """A goal 1 m clear of the default launch file's obstacles (the navigator plans round them)."""
    world = load_launch(ROOT / "launch.toml").launch.world
    while True:
        x, y = rng.uniform(1.0, 10.0), rng.uniform(1.0, 10.0)
        if min(math.hypot(x - o.x, y - o.y) - o.radius for o in world.obstacles) > 1.0:
            return x, y, rng.uniform(0.0, 360.0)


def processes(system: System) -> dict[str, psutil.Process]:
    """Every process of the system: the supervisor (with the router), the zygote, the nodes."""
    launch = psutil.Process(system.proc.pid)
    procs = {"launch (router)": launch}
    for child in launch.children():
        if child.name() == "turtle-zygote":
            procs["zygote"] = child
    procs.update({name: psutil.Process(pid) for name, pid in system.alive.items()})
    return procs


def pss(procs: dict[str, psutil.Process]) -> float:
    """Proportional set size of the whole system, MiB: shared pages (the zygote's imports, which
    every forked node shares) counted once across the processes, not once per process."""
    return sum(p.memory_full_info().pss for p in procs.values()) / 2**20


def cpu_and_memory(procs: dict[str, psutil.Process], seconds: float, work=None) -> dict[str, tuple[float, float]]:
    for p in procs.values():
        p.cpu_percent(None)
    stop = time.monotonic() + seconds
    if work is None:
        time.sleep(seconds)  # pacing: the idle measurement window
    else:
        while time.monotonic() < stop:
            work()
    return {n: (p.cpu_percent(None), p.memory_info().rss / 2**20) for n, p in procs.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--minutes", type=float, default=0.0, help="soak: send goals for N minutes")
    ap.add_argument("--launches", type=int, default=5, help="cold launches timed for launch-to-ready")
    ap.add_argument("--periods", type=int, default=600, help="status periods measured for jitter")
    ap.add_argument(
        "--goals",
        type=int,
        default=30,
        help="goals timed against time_taken (at least; more run while CPU is measured)",
    )
    ap.add_argument("--before", type=Path, help="compare against this checkout of the code before (bench/versus.py)")
    ap.add_argument("--rounds", type=int, default=6, help="with --before: launches of each checkout, alternated")
    ap.add_argument("--no-zygote", action="store_true", help="with --before: also this checkout with every node exec'd")
    args = ap.parse_args()
    if args.before is not None:
        from bench.versus import compare

        compare(ROOT, args.before.resolve(), args.rounds, 15, args.no_zygote)
        return
    rng = random.Random(42)

    print(f"machine: {machine()}")
    turtlectl = [str(Path(sys.executable).parent / "turtlectl")]
    ready = launch_to_ready(args.launches)
    print(f"launch-to-ready (turtlectl launch -> 4 liveliness tokens): {summary(ready, 'ms', 1e3)}")
    bare = wall([sys.executable, "-c", "import zenoh, numpy, msgspec"], 5)
    print(f"bare interpreter importing zenoh, numpy, msgspec: {summary(bare, 'ms', 1e3)}")
    help_wall = wall([*turtlectl, "--help"], 7)
    typer_wall = wall([sys.executable, "-c", "import typer"], 7)
    print(
        f"turtlectl --help: {summary(help_wall, 'ms', 1e3)}; python -c 'import typer': {summary(typer_wall, 'ms', 1e3)}"
    )

    system = System()
    try:
        system.wait_ready(NODES)
        session = zenoh.open(peer_config(system.endpoint))  # a peer, like the nodes: same topology for both streams
        try:
            status = Stamped(session, STATUS, lambda b: decode(b, TurtleStatus).stamp)
            raw = Stamped(session, "bench/raw", lambda b: struct.unpack("<q", b)[0])
            seconds = args.periods / 10.0 + 2.0
            raw_pub = subprocess.Popen([*RAW, "pub", system.endpoint, "bench/raw", "10", str(seconds)])

            # while both streams run: goals for client time vs time_taken, and CPU/RSS
            procs = processes(system)
            idle = cpu_and_memory(procs, 5.0)
            diffs, goal_times, failures = [], [], 0

            def one_goal() -> None:
                nonlocal failures
                response, elapsed = goal(system, *random_goal(rng, system))
                if response is None or not response.success:
                    failures += 1
                    return
                diffs.append(elapsed - response.time_taken)
                goal_times.append(elapsed)

            raw_pub_cpu = raw_cpu(["pub", system.endpoint, "bench/raw62", "62.5", "8"])
            raw_sub_cpu = raw_cpu(["sub", system.endpoint, POSE, "8"])  # the sim's 62.5 Hz poses
            raw_idle = raw_cpu(["idle", system.endpoint, "8"])
            # the floor of the idle system's traffic: one 62.5 Hz publisher and three subscribers of it
            # (the sim's pose to the status monitor, navigator and detector), all raw, together
            floor = raw_group_cpu(
                [["pub", system.endpoint, "bench/floor", "62.5", "8"]]
                + [["sub", system.endpoint, "bench/floor", "8"]] * 3
            )
            echo_wall = wall([*turtlectl, "echo", STATUS, "--once", "--connect", system.endpoint], 5)
            raw_once_wall = wall([*RAW, "once", system.endpoint, STATUS], 5)
            busy = cpu_and_memory(procs, 10.0, one_goal)
            while len(goal_times) + failures < args.goals:
                one_goal()
            raw_pub.wait(seconds + 30)
            deadline = time.monotonic() + 30
            while len(status.samples) < args.periods + 1 and time.monotonic() < deadline:
                time.sleep(0.1)  # pacing: waiting for the last status samples
            status.close()
            raw.close()
        finally:
            close_session(session)

        stamps = status.stamps[: args.periods + 1]
        published = [abs((b - a) / 1e9 - 0.1) for a, b in zip(stamps, stamps[1:], strict=False)]
        print(f"status period |period - 100 ms| at the publisher (stamps): {summary(published, 'ms', 1e3)}")
        arrivals = [t for t, _ in status.samples[: args.periods + 1]]
        jitter = [abs((b - a) - 0.1) for a, b in zip(arrivals, arrivals[1:], strict=False)]
        periods = [b - a for a, b in zip(arrivals, arrivals[1:], strict=False)]
        print(f"status period |period - 100 ms| at the subscriber: {summary(jitter, 'ms', 1e3)}")
        print(f"status mean period: {statistics.mean(periods) * 1e3:.3f} ms (goals running during part of it)")
        lat_ours = [lat for _, lat in status.samples]
        lat_raw = [lat for _, lat in raw.samples]
        print(f"one-way latency robot/status (peer -> peer): {summary(lat_ours, 'ms', 1e3)}")
        print(f"one-way latency raw zenoh-python (peer -> peer): {summary(lat_raw, 'ms', 1e3)}")
        print(f"overhead of our stack (p50 ours / p50 raw): {pct(lat_ours, 50) / pct(lat_raw, 50):.2f}x")
        print(f"goals: {len(goal_times)} reached, {failures} failed; client time {summary(goal_times, 's')}")
        print(f"client time - time_taken: {summary(diffs, 'ms', 1e3)}")
        print("process               idle CPU %   idle RSS MiB   navigating CPU %   navigating RSS MiB")
        for name in procs:
            print(f"{name:20s} {idle[name][0]:11.1f} {idle[name][1]:14.1f} {busy[name][0]:18.1f} {busy[name][1]:20.1f}")
        print(
            f"raw zenoh-python: 62.5 Hz publisher {raw_pub_cpu[0]:.1f} %, 62.5 Hz callback subscriber "
            f"{raw_sub_cpu[0]:.1f} %, idle session {raw_idle[0]:.1f} % and {raw_idle[1]:.1f} MiB"
        )
        print(
            f"raw floor (the idle system's traffic in raw zenoh-python, run together): 62.5 Hz publisher "
            f"{floor[0]:.1f} % + its three subscribers {' + '.join(f'{c:.1f}' for c in floor[1:])} % = {sum(floor):.1f} %"
        )
        idle_cpu = sum(c for c, _ in idle.values())
        idle_rss = sum(r for _, r in idle.values())
        idle_pss = pss(procs)
        print(f"whole system: RSS {idle_rss:.0f} MiB summed per process, PSS {idle_pss:.0f} MiB (shared pages once)")
        rows = [
            (
                "launch -> all nodes ready, p50",
                f"{pct(ready, 50):.2f} s",
                f"bare imports {pct(bare, 50):.2f} s",
                pct(ready, 50) / pct(bare, 50),
                "<= 0.4 s",
            ),
            (
                "`turtlectl --help`, p50",
                f"{pct(help_wall, 50):.2f} s",
                f"import typer {pct(typer_wall, 50):.2f} s",
                pct(help_wall, 50) / pct(typer_wall, 50),
                "<= 0.15 s",
            ),
            (
                "`echo robot/status --once`, p50",
                f"{pct(echo_wall, 50):.2f} s",
                f"raw client {pct(raw_once_wall, 50):.2f} s",
                pct(echo_wall, 50) / pct(raw_once_wall, 50),
                "<= 0.3 s",
            ),
            (
                "idle CPU, whole system",
                f"{idle_cpu:.1f} %",
                f"raw pub + 3 subs {sum(floor):.1f} %",
                idle_cpu / max(sum(floor), 0.1),
                "<= 5 %",
            ),
            (
                "RSS, whole system (summed per process)",
                f"{idle_rss:.0f} MiB",
                f"raw session {raw_idle[1]:.0f} MiB",
                idle_rss / raw_idle[1],
                "<= 200 MiB",
            ),
            ("PSS, whole system (shared pages once)", f"{idle_pss:.0f} MiB", "", math.nan, "<= 200 MiB"),
            (
                "robot/status latency p50",
                f"{pct(lat_ours, 50) * 1e3:.3f} ms",
                f"raw {pct(lat_raw, 50) * 1e3:.3f} ms",
                pct(lat_ours, 50) / pct(lat_raw, 50),
                "<= 1.1x",
            ),
            (
                "robot/status latency p99",
                f"{pct(lat_ours, 99) * 1e3:.3f} ms",
                f"raw {pct(lat_raw, 99) * 1e3:.3f} ms",
                pct(lat_ours, 99) / pct(lat_raw, 99),
                "<= 1.1x",
            ),
            ("status period, publisher p99", f"{pct(published, 99) * 1e3:.2f} ms", "", math.nan, "<= 0.5 ms"),
            ("status period, subscriber max", f"{max(jitter) * 1e3:.2f} ms", "", math.nan, "<= 10 ms"),
        ]
        print()
        met = {  # each target, checked on this run's figure
            "launch -> all nodes ready, p50": pct(ready, 50) <= 0.4,
            "`turtlectl --help`, p50": pct(help_wall, 50) <= 0.15,
            "`echo robot/status --once`, p50": pct(echo_wall, 50) <= 0.3,
            "idle CPU, whole system": idle_cpu <= 5.0,
            "RSS, whole system (summed per process)": idle_rss <= 200,
            "PSS, whole system (shared pages once)": idle_pss <= 200,
            "robot/status latency p50": pct(lat_ours, 50) / pct(lat_raw, 50) <= 1.1,
            "robot/status latency p99": pct(lat_ours, 99) / pct(lat_raw, 99) <= 1.1,
            "status period, publisher p99": pct(published, 99) <= 0.0005,
            "status period, subscriber max": max(jitter) <= 0.010,
        }
        print("| figure | turtlectl | baseline, same run | ratio | target | met |")
        print("|---|---|---|---|---|---|")
        for figure, ours, baseline, ratio, target in rows:
            shown = "" if math.isnan(ratio) else f"{ratio:.2f}x"
            print(f"| {figure} | {ours} | {baseline} | {shown} | {target} | {'yes' if met[figure] else 'NO'} |")

        if args.minutes > 0:
            soak(system, procs, args.minutes, rng)
    finally:
        system.stop()
        system.kill_everything()


def soak(system: System, procs: dict[str, psutil.Process], minutes: float, rng: random.Random) -> None:
    rss_start = {n: p.memory_info().rss / 2**20 for n, p in procs.items()}
    end = time.monotonic() + minutes * 60
    reached = failed = recharges = 0
    times: list[float] = []
    seen = 0  # system output lines already shown
    while time.monotonic() < end:
        system.check_alive()
        try:
            response, elapsed = goal(system, *random_goal(rng, system))
        except AssertionError as exc:  # e.g. no pose within 5 s: an error of the soak, shown with its context
            response, elapsed = None, 0.0
            print(f"soak error at {minutes * 60 - (end - time.monotonic()):.0f} s: {exc}")
            print("  the system's output since the last error:")
            for line in system.lines[seen:][-40:]:
                print("  " + line.rstrip())
            seen = len(system.lines)
        if response is not None and response.reason == "battery low":
            # what a user does after ~200 goals (0.1 %/m): recharge; a refusal is no error of the system
            system.call(RESET, Reset(), everyone=True)
            recharges += 1
        elif response is not None and response.success:
            reached += 1
            times.append(elapsed)
        else:
            failed += 1
    alive = set(system.alive)
    print(
        f"soak {minutes:g} min: {reached} goals reached, {failed} errors, {recharges} recharges (reset at battery low); "
        f"all nodes alive: {alive == set(NODES)}"
    )
    print(f"soak goal time: {summary(times, 's')}")
    for name, p in procs.items():
        rss = p.memory_info().rss / 2**20
        print(f"soak RSS {name:20s} {rss_start[name]:7.1f} -> {rss:7.1f} MiB ({rss - rss_start[name]:+.1f})")
    errors = [line for line in system.lines if "ERROR" in line or "Traceback" in line]
    print(f"soak error lines in the system's output: {len(errors)}")


if __name__ == "__main__":
    main()
