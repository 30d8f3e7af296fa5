"""A fleet split over two hosts keeps running on the host that stays when the other's link fails.

Two network namespaces stand for two machines, joined by ``tests.integration.wire.Wire``: a TUN
device in each, forwarded by this process, which can drop every packet (link down), drop a
share of them (loss), hold each for a while (latency), or go down and up (flapping).  ``tc
netem`` is not used: kernels built without its scheduler (this project's CI among them) answer
"Specified qdisc kind is unknown", and no packet filter is installed there; a TUN device needs
only the ``tun`` driver, ``ip`` and root, and gives the same real packet-level faults under real
TCP.

Host A runs the simulator and turtle1's and turtle3's nodes, its router on A's address; host B
runs turtle2's nodes, joining A's router.  While B's link fails, on A: turtle1's and turtle3's
``robot/status`` keep their 100 ms period, ``turtle1/pose`` never stops for more than a few
simulator steps, a turtle1 goal succeeds; turtle2's status is back on A within seconds of the
link's return.  One fleet serves the three faults, one after another.
"""

from __future__ import annotations

import json
import queue
import statistics
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from tests.integration.harness import free_port, turtlectl
from tests.integration.test_hosts import Launch, sh
from tests.integration.wire import NoNetwork, Wire
from turtlectl.runtime.endpoint import DEFAULT_PEER_TIMEOUT

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[2]
FLEET = str(ROOT / "examples" / "fleet" / "launch.toml")
STATUS_A = ("robot/status", "turtle3/robot/status")  # turtle1's and turtle3's, made on A
POSE_A = "turtle1/pose"
STATUS_B = "turtle2/robot/status"  # made on B
STEP = 0.016  # s: the simulator's step (62.5 Hz)
BACK_WITHIN = 10.0  # s: turtle2's status arrives on A this soon after the link returns


class Probe:
    """``tests.integration.partition_probe`` in host A: arrivals of A's and B's topics, seen on A."""

    def __init__(self, netns: str, endpoint: str):
        self.proc = subprocess.Popen(
            ["ip", "netns", "exec", netns, sys.executable, "-m", "tests.integration.partition_probe", endpoint]
            + [*STATUS_A, POSE_A, STATUS_B],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            cwd=ROOT,
        )
        self.lines: queue.Queue[str] = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()
        first = self.lines.get(timeout=90)
        assert first == "ready", first

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.put(line.rstrip())

    def first_after_now(self, key: str, within: float) -> float | None:
        """When the next sample on ``key`` arrives, waiting at most ``within`` s; None if none."""
        assert self.proc.stdin is not None
        self.proc.stdin.write("mark\n")
        self.proc.stdin.flush()
        deadline = time.monotonic() + within
        while (left := deadline - time.monotonic()) > 0:
            try:
                line = self.lines.get(timeout=left)
            except queue.Empty:
                return None
            if line.startswith(f"seen {key} "):
                return float(line.split()[2])
        return None

    def arrivals(self) -> dict[str, list[float]]:
        """Every arrival so far, per key; the probe ends."""
        assert self.proc.stdin is not None
        self.proc.stdin.close()
        return json.loads(self.lines.get(timeout=30))


@dataclass
class Fleet:
    wire: Wire
    endpoint: str
    host_a: Launch
    host_b: Launch
    goals: list[str] = field(default_factory=list)

    def goto(self, x: float, y: float) -> subprocess.CompletedProcess[str]:
        return sh(
            "ip", "netns", "exec", self.wire.a, *turtlectl(), "goto", str(x), str(y), "0", "--connect", self.endpoint
        )


@pytest.fixture(scope="module")
def fleet():
    try:
        wire = Wire("tp", "10.231.8.1", "10.231.8.2").__enter__()
    except NoNetwork as exc:
        pytest.skip(f"network namespaces are not available here: {exc}")
    port = free_port()
    endpoint = f"tcp/{wire.a_addr}:{port}"
    host_a = Launch(wire.a, FLEET, "--exclude", "turtle2", "--listen", wire.a_addr, "--insecure", "--port", str(port))
    host_b = None
    try:
        host_a.wait_for(r"all 7 nodes ready", 60)
        host_b = Launch(wire.b, FLEET, "--only", "turtle2", "--connect", endpoint)
        host_b.wait_for(r"all 3 nodes ready", 60)
        yield Fleet(wire, endpoint, host_a, host_b)
    finally:
        if host_b is not None:
            host_b.stop()
        host_a.stop()
        wire.close()


def gaps(times: list[float], start: float, end: float) -> list[float]:
    inside = [t for t in times if start <= t <= end]
    return [b - a for a, b in zip(inside, inside[1:], strict=False)]


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q / 100 * len(ordered)))]


def endure(fleet: Fleet, fault, goal: tuple[float, float]) -> None:
    """Watch host A while ``fault()`` runs (it returns when the link is whole again), with a
    turtle1 goal sent from A in the fault's middle; then judge A's rates and turtle2's return."""
    probe = Probe(fleet.wire.a, fleet.endpoint)
    outcome: list[subprocess.CompletedProcess[str]] = []
    start = time.monotonic()
    faulting = threading.Thread(target=fault)
    faulting.start()
    time.sleep(8.0)  # the fault: the goal starts once it has lasted this long
    outcome.append(fleet.goto(*goal))
    faulting.join()
    end = time.monotonic()
    back = probe.first_after_now(STATUS_B, BACK_WITHIN)  # turtle2's status arrives on A again
    arrivals = probe.arrivals()
    report = f"wire: {fleet.wire.forwarded} forwarded, {fleet.wire.dropped} dropped"
    pose_gap = max(
        (b - a, a - start) for a, b in zip(arrivals[POSE_A], arrivals[POSE_A][1:], strict=False) if a > start
    )
    report += f"; longest turtle1/pose gap {pose_gap[0]:.2f} s from {pose_gap[1]:.2f} s into the fault"
    assert outcome[0].returncode == 0, outcome[0].stdout + outcome[0].stderr + report
    for key in STATUS_A:
        periods = gaps(arrivals[key], start, end)
        assert abs(statistics.median(periods) - 0.1) <= 0.01, (key, statistics.median(periods), report)
        assert percentile(periods, 90) <= 0.15, (key, percentile(periods, 90), max(periods), report)
        # a pause, never a stop: a message that may not be dropped waits BLOCKED_LINK_WAIT for room toward
        # B, with the process's routing waiting behind it (zenoh#1876), and a link reopened into a flap's
        # next down phase can queue several such waits (2.4 s seen once, in a full `make test`); nothing
        # bound for a silent peer waits longer than the peer timeout, the bound the docs promise
        assert max(periods) < DEFAULT_PEER_TIMEOUT, (key, max(periods), report)
    pose = gaps(arrivals[POSE_A], start, end)
    # 15 steps: closing the links to the silent host (at its lease, TURTLECTL_PEER_TIMEOUT after the
    # fault starts) costs host A's processes up to ~170 ms on a loaded 2-core machine; a stall is seconds
    assert max(pose) <= 15 * STEP, (max(pose), percentile(pose, 99), report)
    assert back is not None, f"turtle2's status not back on A within {BACK_WITHIN} s of the link"
    periods = gaps(arrivals[STATUS_A[0]], start, end)
    print(  # the figures of docs/how-to/fleet-across-hosts.md (pytest -s shows them)
        f"\n{report}; robot/status period median {statistics.median(periods) * 1000:.1f} ms, "
        f"p90 {percentile(periods, 90) * 1000:.1f} ms, max {max(periods) * 1000:.0f} ms; "
        f"longest turtle1/pose gap {max(pose) * 1000:.0f} ms; turtle2 back {back - end:.2f} s after the link"
    )


def test_host_a_runs_on_through_host_b_link_down_for_20_s(fleet):
    def down() -> None:
        fleet.wire.down = True
        time.sleep(20.0)  # the fault: host B's link is down this long
        fleet.wire.down = False

    endure(fleet, down, (7.5, 5.5))


def test_host_a_runs_on_through_30_percent_loss_and_200_ms_latency_on_host_b_s_link(fleet):
    def lossy() -> None:
        fleet.wire.loss, fleet.wire.latency = 0.3, 0.2
        time.sleep(20.0)  # the fault: host B's link is lossy and slow this long
        fleet.wire.loss, fleet.wire.latency = 0.0, 0.0

    endure(fleet, lossy, (3.0, 7.5))


def test_host_a_runs_on_through_host_b_s_link_flapping(fleet):
    def flapping() -> None:
        fleet.wire.flap(up=2.0, down=2.0, until=time.monotonic() + 20.0)  # the fault: 2 s down, 2 s up, for 20 s

    endure(fleet, flapping, (7.5, 5.5))
