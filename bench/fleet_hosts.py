"""Benchmark of a fleet split over two hosts (the same N turtles as bench/fleet.py): two
network namespaces joined by a virtual cable stand for two machines, as
tests/integration/test_hosts.py makes them.  Host A runs the simulator and the first half of the
turtles' nodes (``--exclude`` the rest, listening on its cable address), host B the other half
(``--only turtleK`` for each, joining A's router).  Per N: idle CPU per host, every turtle's
status period at a subscriber on host A (stamps at the publisher, arrivals at the subscriber), and
three rounds of goals for every turtle at once, as bench/fleet.py measures them on one host (whose
functions this uses).  The two namespaces share this machine's cores: the split shows what each host
carries and that the fleet works over a network, not more capacity.

Needs root (``ip netns``).  Usage: python bench/fleet_hosts.py [--turtles 10]
(measures from inside host A: ``--measure ENDPOINT N`` is this script run there).  With
``--fault down|loss|flap`` (repeatable) [``--before DIR``] it measures what host A keeps while host
B's link fails instead (bench/fleet_faults.py).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import secrets
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import psutil

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

import fleet  # noqa: E402  (the launch file, status periods and goals of bench/fleet.py)

A_ADDR, B_ADDR = "10.231.9.1", "10.231.9.2"


def sh(*argv: str) -> None:
    subprocess.run(list(argv), check=True, capture_output=True, text=True, timeout=20)


def network() -> tuple[str, str, str]:
    """Two network namespaces joined by a veth pair: (a, b, tag)."""
    tag = secrets.token_hex(3)
    a, b = f"bf-a-{tag}", f"bf-b-{tag}"
    sh("ip", "netns", "add", a)
    sh("ip", "netns", "add", b)
    sh("ip", "link", "add", f"fa{tag}", "type", "veth", "peer", "name", f"fb{tag}")
    sh("ip", "link", "set", f"fa{tag}", "netns", a)
    sh("ip", "link", "set", f"fb{tag}", "netns", b)
    sh("ip", "-n", a, "addr", "add", f"{A_ADDR}/30", "dev", f"fa{tag}")
    sh("ip", "-n", b, "addr", "add", f"{B_ADDR}/30", "dev", f"fb{tag}")
    for ns, dev in ((a, f"fa{tag}"), (b, f"fb{tag}")):
        sh("ip", "-n", ns, "link", "set", dev, "up")
        sh("ip", "-n", ns, "link", "set", "lo", "up")
    return a, b, tag


class Host:
    """`turtlectl launch` in a network namespace, its output collected."""

    def __init__(self, netns: str, *args: str):
        self.lines: list[str] = []
        self.proc = subprocess.Popen(
            ["ip", "netns", "exec", netns, sys.executable, "-m", "turtlectl.cli", "launch", *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
            env={**os.environ, "PYTHONUNBUFFERED": "1"},
        )
        threading.Thread(target=lambda: self.lines.extend(self.proc.stdout), daemon=True).start()  # type: ignore[arg-type]

    def wait_for(self, pattern: str, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        while not any(re.search(pattern, line) for line in self.lines):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"no {pattern!r}:\n" + "".join(self.lines))
            time.sleep(0.1)  # pacing: polling the collected output under a deadline

    def pids(self) -> list[int]:
        try:
            root = psutil.Process(self.proc.pid)
            return [p.pid for p in [root, *root.children(recursive=True)] if p.name() != "ip"]
        except psutil.Error:
            return []

    def stop(self) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGINT)
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)


def measure_inside(endpoint: str, n: int, periods: int) -> None:
    """Run in host A: every turtle's status period, then the goals; printed as one JSON line."""
    turtles = fleet.names(n)
    streams = fleet.status_periods(endpoint, turtles, periods, timeout=(periods + fleet.SETTLE) / 10 + 30)
    status = {
        name: (
            fleet.pct(fleet.deviations([t / 1e9 for t in s.stamps], periods), 99),
            max(fleet.deviations(s.arrivals, periods), default=math.nan),
        )
        for name, s in streams.items()
    }
    goals = fleet.run_goals(endpoint, turtles, fleet.goal_rounds(False))
    print(json.dumps({"status": status, "goals": goals}))


def run(n: int, periods: int) -> dict[str, object]:
    a, b, tag = network()
    port = fleet.port_in_range()
    endpoint = f"tcp/{A_ADDR}:{port}"
    folder = Path(tempfile.mkdtemp(prefix="bench-fleet-hosts-"))
    path = folder / f"fleet{n}.toml"
    path.write_text(fleet.launch_file(n))
    there = fleet.names(n)[(n + 1) // 2 :]  # host B's turtles
    host_a = host_b = None
    try:
        excluded = [arg for name in there for arg in ("--exclude", name)]
        host_a = Host(a, str(path), *excluded, "--listen", A_ADDR, "--insecure", "--port", str(port))
        host_a.wait_for(r"nodes? ready in", 120)
        host_b = Host(b, str(path), *[arg for name in there for arg in ("--only", name)], "--connect", endpoint)
        host_b.wait_for(r"nodes? ready in", 120)
        time.sleep(5.0)  # pacing: the system settles after start before the idle window
        hosts = {"A": host_a.pids(), "B": host_b.pids()}
        procs = {pid: psutil.Process(pid) for pids in hosts.values() for pid in pids}
        windows: list[dict[int, float]] = []
        for p in procs.values():
            p.cpu_percent(None)
        for _ in range(4):
            time.sleep(2.0)  # a CPU window
            windows.append({pid: p.cpu_percent(None) for pid, p in procs.items()})
        cpu = {
            host: statistics.median(sum(w.get(pid, 0.0) for pid in pids) for w in windows)
            for host, pids in hosts.items()
        }
        inside = subprocess.run(
            [
                "ip",
                "netns",
                "exec",
                a,
                sys.executable,
                __file__,
                "--measure",
                endpoint,
                str(n),
                "--periods",
                str(periods),
            ],
            capture_output=True,
            text=True,
            timeout=600,
        )
        if inside.returncode != 0:
            raise RuntimeError(inside.stdout + inside.stderr)
        found = json.loads(inside.stdout.strip().splitlines()[-1])
        return {"n": n, "cpu": cpu, "split": (n - len(there), len(there)), **found}
    finally:
        for host in (host_b, host_a):
            if host is not None:
                host.stop()
        subprocess.run(["ip", "netns", "del", a], capture_output=True)
        subprocess.run(["ip", "netns", "del", b], capture_output=True)


def show(result: dict[str, object]) -> str:
    status: dict[str, list[float]] = result["status"]  # type: ignore[assignment]
    goals: list[dict[str, list[object]]] = result["goals"]  # type: ignore[assignment]
    cpu: dict[str, float] = result["cpu"]  # type: ignore[assignment]
    reached = sum(1 for r in goals for v in r.values() if v[0])
    total = sum(len(r) for r in goals)
    times = [v[1] for r in goals for v in r.values() if v[0]]
    worst_pub = max(v[0] for v in status.values())
    sub = sorted(v[1] for v in status.values())
    a, b = result["split"]  # type: ignore[misc]
    return (
        f"| {result['n']} | {a} + {b} | {cpu['A']:.1f} % | {cpu['B']:.1f} % | {worst_pub * 1e3:.2f} ms | "
        f"{statistics.median(sub) * 1e3:.1f} / {sub[-1] * 1e3:.1f} ms | {reached}/{total} | "
        f"{statistics.mean(times):.3f} s |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--turtles", type=int, default=10)
    parser.add_argument("--periods", type=int, default=50)
    parser.add_argument("--measure", nargs=2, metavar=("ENDPOINT", "N"), help=argparse.SUPPRESS)
    parser.add_argument("--fault", action="append", choices=("down", "loss", "flap"), help="a fault on host B's link")
    parser.add_argument("--before", type=Path, help="with --fault: a checkout of the code before, with its .venv")
    parser.add_argument("--rounds", type=int, default=1, help="with --fault: runs of each, alternated")
    args = parser.parse_args()
    if args.fault:
        import fleet_faults

        print(f"machine: {fleet.machine()}")
        fleet_faults.run(args.fault, args.before, args.rounds)
        return
    if args.measure:
        measure_inside(args.measure[0], int(args.measure[1]), args.periods)
        return
    print(f"machine: {fleet.machine()}")
    print(f"load average at start: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    result = run(args.turtles, args.periods)
    print(
        "| N | turtles on host A + B | idle CPU host A | idle CPU host B | status publisher p99 |period - 100 ms| "
        "(worst) | status subscriber max (median / worst) | goals reached | mean time_taken |"
    )
    print("|---|---|---|---|---|---|---|---|")
    print(show(result))


if __name__ == "__main__":
    main()
