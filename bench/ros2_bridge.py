"""The ROS 2 bridge's cost: latency of turtlectl's pose to an rclpy callback (as /turtle1/odom), and the
bridge process's CPU, idle (no ROS peer) and while an rclpy node subscribes.

Needs root (a network namespace holding only loopback, as the tests) and `make ros2-side`:

    .venv/bin/python bench/ros2_bridge.py [--count 1000] [--seconds 10]

Prints one JSON object.  Latency is the odometry's header stamp (the simulator's wall-clock stamp of
the pose) to the rclpy callback's time.time_ns(): Zenoh hop, the bridge's conversion, DDS to Fast DDS.
"""

from __future__ import annotations

import argparse
import json
import os
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


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=1000, help="odometry messages timed")
    parser.add_argument("--seconds", type=float, default=10.0, help="each CPU window (s)")
    args = parser.parse_args()
    with ros_side() as side, tempfile.TemporaryDirectory() as folder:
        system = side.launch(default_launch_with_bridge(), Path(folder), nodes=5)
        pid = int(system.wait_for(r"started ros2_bridge \(pid (\d+)\)").rsplit("pid ", 1)[1].rstrip(")"))
        system.wait_for("bridging turtle1")
        idle = cpu_percent(pid, args.seconds)
        probe = side.rclpy("probe.py", "latency", str(args.count))
        probe.wait_for("^READY$")
        busy = cpu_percent(pid, args.seconds)
        latency = probe.json_line("LATENCY", timeout=60 + args.count / 50)
    print(
        json.dumps(
            {
                "pose_to_rclpy_odom": latency,
                "bridge_cpu_percent_no_ros_peer": idle,
                "bridge_cpu_percent_one_rclpy_subscriber": busy,
            }
        )
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
