"""Benchmark of the whole system, measured side by side in one run.

Reports: launch-to-ready time; status period jitter at a subscriber; goal time
as the client sees it vs the navigator's time_taken; one-way latency of
robot/status next to raw zenoh-python pub/sub in the same topology; CPU and
memory per process, idle and navigating; with --minutes N, a soak that sends
goals back to back for N minutes and counts errors and memory growth.

Usage: python bench/system.py [--minutes N] [--launches N] [--periods N]
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

from cli.launchfile import load_launch  # noqa: E402
from messages import NavigateToResponse, TurtleStatus, decode  # noqa: E402
from messages.keys import STATUS  # noqa: E402
from nodes.goal import path_problem  # noqa: E402
from runtime.session import close_session, peer_config  # noqa: E402
from tests.integration.harness import NODES, System  # noqa: E402  (the same launcher as the tests)


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
        f"Python {platform.python_version()}; eclipse-zenoh {metadata.version('eclipse-zenoh')}"
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
    """A peer subscriber that records (arrival monotonic, one-way latency s, payload)."""

    def __init__(self, session: zenoh.Session, key: str, stamp_of):
        self.samples: list[tuple[float, float]] = []
        self._stamp_of = stamp_of
        self._sub = session.declare_subscriber(key, self._on)

    def _on(self, sample: zenoh.Sample) -> None:
        now_wall, now = time.time_ns(), time.monotonic()
        self.samples.append((now, (now_wall - self._stamp_of(sample.payload.to_bytes())) / 1e9))

    def close(self) -> None:
        self._sub.undeclare()


def goal(system: System, x: float, y: float, theta: float) -> tuple[NavigateToResponse | None, float]:
    try:
        response, elapsed, _ = system.navigate(x, y, theta, timeout=40.0)
    except AssertionError as exc:  # an error reply: counted as a failure
        print(f"goal ({x:.2f}, {y:.2f}, {theta:.0f}) failed: {exc}")
        return None, 0.0
    return response, elapsed


def random_goal(rng: random.Random, system: System) -> tuple[float, float, float]:
    """A goal 1.5 m clear of the default launch file's obstacles whose straight way from where
    the turtle is does not meet one (the navigator refuses those at once: no planner yet)."""
    here = system.latest_pose()
    world = load_launch(ROOT / "launch.toml").launch.world
    while True:
        x, y = rng.uniform(1.0, 10.0), rng.uniform(1.0, 10.0)
        clear = min(math.hypot(x - o.x, y - o.y) - o.radius for o in world.obstacles) > 1.0
        if clear and path_problem(here.x, here.y, x, y, world, 0.5) is None:
            return x, y, rng.uniform(0.0, 360.0)


def processes(system: System) -> dict[str, psutil.Process]:
    procs = {"launch (router)": psutil.Process(system.proc.pid)}
    procs.update({name: psutil.Process(pid) for name, pid in system.alive.items()})
    return procs


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
    ap.add_argument("--goals", type=int, default=30, help="goals timed against time_taken")
    args = ap.parse_args()
    rng = random.Random(42)

    print(f"machine: {machine()}")
    ready = launch_to_ready(args.launches)
    print(f"launch-to-ready (turtlectl launch -> 4 liveliness tokens): {summary(ready, 'ms', 1e3)}")

    system = System()
    try:
        system.wait_ready(NODES)
        session = zenoh.open(peer_config(system.endpoint))  # a peer, like the nodes: same topology for both streams
        try:
            status = Stamped(session, STATUS, lambda b: decode(b, TurtleStatus).stamp)
            raw = Stamped(session, "bench/raw", lambda b: struct.unpack("<q", b)[0])
            seconds = args.periods / 10.0 + 2.0
            raw_pub = subprocess.Popen(
                [sys.executable, str(ROOT / "bench" / "raw_pub.py"), system.endpoint, "bench/raw", "10", str(seconds)]
            )

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

        if args.minutes > 0:
            soak(system, procs, args.minutes, rng)
    finally:
        system.stop()
        system.kill_everything()


def soak(system: System, procs: dict[str, psutil.Process], minutes: float, rng: random.Random) -> None:
    rss_start = {n: p.memory_info().rss / 2**20 for n, p in procs.items()}
    end = time.monotonic() + minutes * 60
    reached = failed = 0
    times: list[float] = []
    while time.monotonic() < end:
        system.check_alive()
        response, elapsed = goal(system, *random_goal(rng, system))
        if response is not None and response.success:
            reached += 1
            times.append(elapsed)
        else:
            failed += 1
    alive = set(system.alive)
    print(f"soak {minutes:g} min: {reached} goals reached, {failed} errors; all nodes alive: {alive == set(NODES)}")
    print(f"soak goal time: {summary(times, 's')}")
    for name, p in procs.items():
        rss = p.memory_info().rss / 2**20
        print(f"soak RSS {name:20s} {rss_start[name]:7.1f} -> {rss:7.1f} MiB ({rss - rss_start[name]:+.1f})")
    errors = [line for line in system.lines if "ERROR" in line or "Traceback" in line]
    print(f"soak error lines in the system's output: {len(errors)}")


if __name__ == "__main__":
    main()
