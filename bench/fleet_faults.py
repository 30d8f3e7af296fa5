"""Faults on one host's link of a fleet split over two hosts, this checkout against the code
before (alternated in one run): what host A keeps while host B's link is down, lossy and slow, or
flapping.

Two network namespaces joined by ``tests.integration.wire.Wire`` (a forwarded TUN cable: this
kernel has no netem) stand for two machines, as tests/integration/test_partition.py makes them:
host A runs the simulator and turtle1's and turtle3's nodes of examples/fleet (its router on A's
address), host B turtle2's.  A watcher on A (tests.integration.partition_probe) notes every
arrival of ``robot/status`` (turtle1's), ``turtle1/pose`` and ``turtle2/robot/status`` through
``SECONDS`` s of the fault; printed: the status period's median, p90 and max, the longest pose gap,
and how soon after the link turtle2's status is back on A.  Machines here are shared and noisy.

Needs root.  Usage: python bench/fleet_hosts.py --fault down|loss|flap [--before DIR] [--rounds 2]
(``--before``: a checkout of the code before with its .venv, e.g. ``git worktree add ../before HEAD~5``).
"""

from __future__ import annotations

import json
import queue
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.integration.harness import free_port  # noqa: E402
from tests.integration.wire import Wire  # noqa: E402

FLEET = ROOT / "examples" / "fleet" / "launch.toml"
STATUS_A, POSE_A, STATUS_B = "robot/status", "turtle1/pose", "turtle2/robot/status"
SECONDS = 20.0  # s of each fault
FAULTS = ("down", "loss", "flap")


def _lines(proc: subprocess.Popen[str]) -> queue.Queue[str]:
    out: queue.Queue[str] = queue.Queue()

    def read() -> None:
        assert proc.stdout is not None
        for line in proc.stdout:
            out.put(line.rstrip())

    threading.Thread(target=read, daemon=True).start()
    return out


def _wait(lines: queue.Queue[str], text: str, timeout: float) -> list[str]:
    seen: list[str] = []
    deadline = time.monotonic() + timeout
    while (left := deadline - time.monotonic()) > 0:
        try:
            line = lines.get(timeout=left)
        except queue.Empty:
            break
        seen.append(line)
        if text in line:
            return seen
    raise RuntimeError(f"no {text!r} within {timeout} s:\n" + "\n".join(seen[-30:]))


def _fault(wire: Wire, fault: str) -> None:
    if fault == "down":
        wire.down = True
        time.sleep(SECONDS)  # the fault lasts this long
        wire.down = False
    elif fault == "loss":
        wire.loss, wire.latency = 0.3, 0.2
        time.sleep(SECONDS)  # the fault lasts this long
        wire.loss, wire.latency = 0.0, 0.0
    else:
        wire.flap(up=2.0, down=2.0, until=time.monotonic() + SECONDS)


def one(python: str, fault: str) -> dict[str, float]:
    """One fleet run by ``python`` (a checkout's interpreter) through ``fault``: host A's figures."""
    with Wire("bq", "10.231.6.1", "10.231.6.2") as wire:
        port = free_port()
        endpoint = f"tcp/{wire.a_addr}:{port}"
        launch = [python, "-m", "turtlectl.cli", "launch", str(FLEET)]
        procs = []
        try:
            for netns, args in (
                (wire.a, ["--exclude", "turtle2", "--listen", wire.a_addr, "--insecure", "--port", str(port)]),
                (wire.b, ["--only", "turtle2", "--connect", endpoint]),
            ):  # host A first: host B joins its router
                host = subprocess.Popen(
                    ["ip", "netns", "exec", netns, *launch, *args],
                    stdout=subprocess.PIPE,
                    stderr=subprocess.STDOUT,
                    text=True,
                    start_new_session=True,
                )
                procs.append(host)
                _wait(_lines(host), "nodes ready", 120)
            probe = subprocess.Popen(
                ["ip", "netns", "exec", wire.a, python, "-m", "tests.integration.partition_probe", endpoint]
                + [STATUS_A, POSE_A, STATUS_B],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=subprocess.STDOUT,
                text=True,
                cwd=ROOT,
            )
            procs.append(probe)
            lines = _lines(probe)
            _wait(lines, "ready", 90)
            start = time.monotonic()
            _fault(wire, fault)
            end = time.monotonic()
            assert probe.stdin is not None
            probe.stdin.write("mark\n")
            probe.stdin.flush()
            back = float("nan")
            try:
                seen = _wait(lines, f"seen {STATUS_B} ", 30)
                back = float(seen[-1].split()[2]) - end
            except RuntimeError:
                pass
            probe.stdin.close()
            arrivals = json.loads(_wait(lines, "{", 30)[-1])
        finally:
            for proc in procs:
                subprocess.run(["kill", "-INT", f"-{proc.pid}"], capture_output=True)
                if proc.poll() is None:
                    proc.terminate()
                try:
                    proc.wait(15)
                except subprocess.TimeoutExpired:
                    proc.kill()
    status = [b - a for a, b in zip(arrivals[STATUS_A], arrivals[STATUS_A][1:], strict=False) if start <= a <= end]
    pose = [b - a for a, b in zip(arrivals[POSE_A], arrivals[POSE_A][1:], strict=False) if start <= a <= end]
    ordered = sorted(status)
    return {
        "median": statistics.median(status),
        "p90": ordered[int(0.9 * (len(ordered) - 1))],
        "max": max(status),
        "pose_gap": max(pose),
        "back": back,
    }


def run(faults: list[str], before: Path | None, rounds: int) -> None:
    pythons = {"this": sys.executable} | ({"before": str(before / ".venv" / "bin" / "python")} if before else {})
    print("| fault | code | status period median / p90 / max | longest pose gap | turtle2 back after the link |")
    print("|---|---|---|---|---|")
    for fault in faults:
        for _ in range(rounds):
            for name, python in pythons.items():  # alternated: the machine's load falls on both alike
                got = one(python, fault)
                print(
                    f"| {fault} | {name} | {got['median'] * 1e3:.1f} / {got['p90'] * 1e3:.1f} / {got['max'] * 1e3:.0f} ms "
                    f"| {got['pose_gap'] * 1e3:.0f} ms | {got['back']:.1f} s |",
                    flush=True,
                )
