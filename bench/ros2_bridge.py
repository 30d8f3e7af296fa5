"""The ROS 2 bridge's cost beside plain rclpy's, in one run: latency of turtlectl's pose to an rclpy
callback (as /turtle1/odom) and the bridge process's CPU, idle (no ROS peer) and while an rclpy node
subscribes; against an rclpy node publishing the same odometry at the same rate (62.5 Hz) to the same
subscriber, and that publisher's CPU.  Rounds alternate the two, the machine being shared and noisy.

Needs root (a network namespace holding only loopback, as the tests) and `make ros2-side`:

    .venv/bin/python bench/ros2_bridge.py [--count 1000] [--seconds 10] [--rounds 2]

Prints one JSON object per round and variant, then medians over the rounds with the machine.  Latency is
the odometry's header stamp (a wall-clock stamp: the simulator's, or the rclpy publisher's) to the rclpy
callback's time.time_ns(); through the bridge: Zenoh hop, the bridge's conversion, DDS to Fast DDS.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests.integration.ros2_side import default_launch_with_bridge, ros_side  # noqa: E402

TICKS = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS  # utime + stime


def cpu_percent(pid: int, seconds: float) -> float:
    start, t0 = cpu_seconds(pid), time.monotonic()
    time.sleep(seconds)  # the measurement window itself
    return round(100 * (cpu_seconds(pid) - start) / (time.monotonic() - t0), 2)


POSE_RATE = 62.5  # Hz: the simulator's pose rate, which the plain rclpy publisher keeps too


def plain_rclpy(count: int, seconds: float) -> dict:
    """An rclpy publisher of /turtle1/odom at POSE_RATE to the same subscriber: latency, its CPU."""
    with ros_side() as side:
        publisher = side.rclpy("probe.py", "odom", str(POSE_RATE), str(30 + seconds + count / POSE_RATE))
        publisher.wait_for("^READY$")
        probe = side.rclpy("probe.py", "latency", str(count))
        probe.wait_for("^READY$")
        busy = cpu_percent(publisher.proc.pid, seconds)
        latency = probe.json_line("LATENCY", timeout=60 + count / 50)
    return {"variant": "rclpy", "latency": latency, "publisher_cpu_percent_one_subscriber": busy}


def bridged(count: int, seconds: float) -> dict:
    with ros_side() as side, tempfile.TemporaryDirectory() as folder:
        system = side.launch(default_launch_with_bridge(), Path(folder), nodes=5)
        pid = int(system.wait_for(r"started ros2_bridge \(pid (\d+)\)").rsplit("pid ", 1)[1].rstrip(")"))
        system.wait_for("bridging turtle1")
        idle = cpu_percent(pid, seconds)
        probe = side.rclpy("probe.py", "latency", str(count))
        probe.wait_for("^READY$")
        busy = cpu_percent(pid, seconds)
        latency = probe.json_line("LATENCY", timeout=60 + count / 50)
    return {
        "variant": "bridge",
        "latency": latency,
        "bridge_cpu_percent_no_ros_peer": idle,
        "bridge_cpu_percent_one_rclpy_subscriber": busy,
    }


def median_of(rows: list[dict], *path: str) -> float:
    values = []
    for row in rows:
        value = row
        for step in path:
            value = value[step]
        values.append(value)
    return round(statistics.median(values), 3)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=1000, help="odometry messages timed per round")
    parser.add_argument("--seconds", type=float, default=10.0, help="each CPU window (s)")
    parser.add_argument("--rounds", type=int, default=2, help="rounds, each running both variants (order alternated)")
    args = parser.parse_args()
    results: dict[str, list[dict]] = {"bridge": [], "rclpy": []}
    for round_ in range(args.rounds):
        order = (bridged, plain_rclpy) if round_ % 2 == 0 else (plain_rclpy, bridged)
        for run in order:
            row = run(args.count, args.seconds)
            print(json.dumps(row), flush=True)
            results[row["variant"]].append(row)
    bridge, rclpy = results["bridge"], results["rclpy"]
    summary = {
        "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}",
        "rounds": args.rounds,
        "latency_p50_ms": {
            "bridge": median_of(bridge, "latency", "p50_ms"),
            "rclpy": median_of(rclpy, "latency", "p50_ms"),
        },
        "latency_p90_ms": {
            "bridge": median_of(bridge, "latency", "p90_ms"),
            "rclpy": median_of(rclpy, "latency", "p90_ms"),
        },
        "cpu_percent_one_subscriber": {
            "bridge": median_of(bridge, "bridge_cpu_percent_one_rclpy_subscriber"),
            "rclpy_publisher": median_of(rclpy, "publisher_cpu_percent_one_subscriber"),
        },
        "bridge_cpu_percent_no_ros_peer": median_of(bridge, "bridge_cpu_percent_no_ros_peer"),
    }
    print("SUMMARY " + json.dumps(summary), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
