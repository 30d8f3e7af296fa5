"""Cyclone DDS (Python binding) <-> real rclpy (pip wheels, Fast DDS): does a message cross, and how fast?

Not part of `make test` or `make bench` yet: it needs the optional ROS 2 packages in .venv (see
docs/notes-ros2-bridge.md for the exact pip command) and root, for a network namespace holding only
loopback (Fast DDS's localhost mode still advertises the network card's address; in the namespace no DDS
packet can leave 127.0.0.1).

    .venv/bin/python bench/ros2_interop.py              # every case, 100 messages each
    .venv/bin/python bench/ros2_interop.py --count 50 --no-ignore-type-information

Cases (each rclpy side is its own process, as a student's node would be):
  twist-to-rclpy   Cyclone writer geometry_msgs/Twist on rt/turtle1/cmd_vel -> rclpy subscription
  scan-to-rclpy    Cyclone writer sensor_msgs/LaserScan (360 ranges) on rt/obstacles -> rclpy subscription
  twist-from-rclpy rclpy publisher /turtle1/cmd_vel -> Cyclone reader
  graph            what rclpy's graph lists of the Cyclone side (topics and types, turtlesim/msg/Pose included)
QoS on both sides: reliable, volatile, keep last 10 (rclpy's default, the integer 10 in create_publisher).
Prints one JSON object per case: received/sent, latency p50/p90/max in ms (monotonic clock, same host),
values checked equal.
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

NETNS_FLAG = "TURTLECTL_ROS2_LOOPBACK_NETNS"
DEADLINE = 30.0  # s, for matching and for a case's messages


def cyclone_config(ignore_type_information: bool) -> str:
    """Cyclone DDS on loopback only, unicast discovery to 127.0.0.1 (as Fast DDS's localhost mode)."""
    compat = (
        "<Compatibility><IgnoreTypeInformation>1.15</IgnoreTypeInformation></Compatibility>"
        if ignore_type_information
        else ""
    )
    return (
        "<CycloneDDS><Domain Id='any'>"
        "<General><Interfaces><NetworkInterface address='127.0.0.1'/></Interfaces>"
        "<AllowMulticast>false</AllowMulticast></General>"
        "<Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>20</MaxAutoParticipantIndex>"
        "<Peers><Peer address='127.0.0.1'/></Peers></Discovery>"
        f"{compat}</Domain></CycloneDDS>"
    )


def ros_env(ignore_type_information: bool) -> dict[str, str]:
    env = dict(os.environ)
    env.update(
        ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
        ROS_DOMAIN_ID=env.get("ROS_DOMAIN_ID", "0"),
        RMW_IMPLEMENTATION="rmw_fastrtps_cpp",
        CYCLONEDDS_URI=cyclone_config(ignore_type_information),
    )
    return env


def percentiles(latencies_ms: list[float]) -> dict[str, float]:
    if not latencies_ms:
        return {}
    ordered = sorted(latencies_ms)
    return {
        "p50_ms": round(statistics.median(ordered), 3),
        "p90_ms": round(ordered[int(0.9 * (len(ordered) - 1))], 3),
        "max_ms": round(ordered[-1], 3),
    }


# ---------------------------------------------------------------- the rclpy side (child processes)


def rclpy_sub(kind: str, count: int) -> None:
    """Subscribe with rclpy, print READY, then one JSON line with what arrived."""
    import rclpy
    from rclpy.node import Node

    if kind == "twist":
        from geometry_msgs.msg import Twist as Msg

        topic = "/turtle1/cmd_vel"
    else:
        from sensor_msgs.msg import LaserScan as Msg

        topic = "/obstacles"
    rclpy.init()
    node = Node("probe_sub")
    got: list[tuple[float, object]] = []
    node.create_subscription(Msg, topic, lambda m: got.append((time.monotonic(), m)), 10)
    print("READY", flush=True)
    end = time.monotonic() + DEADLINE
    while len(got) < count and time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.1)
    latencies, bad = [], 0
    for received, m in got:
        if kind == "twist":
            latencies.append((received - m.linear.y) * 1e3)
            bad += m.angular.x != 0.5 or m.linear.z != -1.25
        else:
            sent = m.header.stamp.sec + m.header.stamp.nanosec * 1e-9  # the monotonic clock, as sec/nanosec
            latencies.append((received - sent) * 1e3)
            i = int(m.angle_min)
            want = [float(i + k / 4) for k in range(360)]
            bad += list(m.ranges) != want or m.header.frame_id != "turtle1/base_scan"
    print(json.dumps({"received": len(got), "wrong_values": bad, **percentiles(latencies)}), flush=True)
    node.destroy_node()
    rclpy.shutdown()


def rclpy_pub(count: int) -> None:
    """Publish Twist with rclpy once a subscription matched; monotonic send time in linear.y."""
    import rclpy
    from geometry_msgs.msg import Twist
    from rclpy.node import Node

    rclpy.init()
    node = Node("probe_pub")
    pub = node.create_publisher(Twist, "/turtle1/cmd_vel", 10)
    end = time.monotonic() + DEADLINE
    while pub.get_subscription_count() < 1 and time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.05)
    print("READY" if pub.get_subscription_count() else "NOMATCH", flush=True)
    # matching is per side: this writer saw the reader, the reader may not have seen this writer yet
    # (then the first samples are lost, volatile QoS); the parent says GO once its reader matched
    sys.stdin.readline()
    for i in range(count):
        m = Twist()
        m.linear.x, m.linear.y, m.angular.x = float(i), time.monotonic(), 0.5
        pub.publish(m)
        time.sleep(0.01)  # 100 Hz pacing, not a readiness wait
    time.sleep(1.0)  # let reliable repairs finish before the participant goes
    node.destroy_node()
    rclpy.shutdown()


def rclpy_graph(wanted: str) -> None:
    """Print rclpy's view of the graph once every topic named in `wanted` (comma separated) shows."""
    import rclpy
    from rclpy.node import Node

    rclpy.init()
    node = Node("probe_graph")
    names = set(wanted.split(","))
    end = time.monotonic() + DEADLINE
    topics: dict[str, list[str]] = {}
    while time.monotonic() < end:
        topics = dict(node.get_topic_names_and_types())
        if names <= topics.keys():
            break
        rclpy.spin_once(node, timeout_sec=0.1)
    print(json.dumps({"topics": topics, "nodes": node.get_node_names_and_namespaces()}), flush=True)
    node.destroy_node()
    rclpy.shutdown()


# ---------------------------------------------------------------- the Cyclone side (this process)


def child(env: dict[str, str], *args: str) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, __file__, "--role", *args],
        env=env,
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
        bufsize=1,
    )


def wait_matched(entity, status_name: str) -> float:
    """Seconds until the Cyclone entity has a matched peer (DEADLINE at most)."""
    start = time.monotonic()
    while time.monotonic() - start < DEADLINE:
        if getattr(entity, status_name)().current_count > 0:
            return time.monotonic() - start
        time.sleep(0.005)
    return -1.0


def case_to_rclpy(kind: str, count: int, env: dict[str, str]) -> dict:
    from cyclonedds.domain import DomainParticipant
    from cyclonedds.pub import DataWriter
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.topic import Topic

    from turtlectl.nodes import ros2_types as r

    proc = child(env, "rclpy-sub", kind, str(count))
    assert proc.stdout.readline().strip() == "READY"
    dp = DomainParticipant(int(env["ROS_DOMAIN_ID"]))
    qos = Qos(Policy.Reliability.Reliable(0), Policy.Durability.Volatile, Policy.History.KeepLast(10), r.XCDR1)
    msg_type, ros_topic = (r.Twist, "/turtle1/cmd_vel") if kind == "twist" else (r.LaserScan, "/obstacles")
    writer = DataWriter(dp, Topic(dp, r.dds_topic(ros_topic), msg_type, qos=qos), qos=qos)
    matched_s = wait_matched(writer, "get_publication_matched_status")
    if matched_s >= 0:
        for i in range(count):
            now = time.monotonic()
            if kind == "twist":
                writer.write(r.Twist(linear=r.Vector3(x=float(i), y=now, z=-1.25), angular=r.Vector3(x=0.5)))
            else:
                sec = int(now)
                stamp = r.Time(sec=sec, nanosec=int((now - sec) * 1e9))
                writer.write(
                    r.LaserScan(
                        header=r.Header(stamp=stamp, frame_id="turtle1/base_scan"),
                        angle_min=float(i),
                        ranges=[float(i + k / 4) for k in range(360)],
                    )
                )
            time.sleep(0.01)
    out = json.loads(proc.stdout.readline() or "{}")
    proc.wait(timeout=DEADLINE)
    del writer, dp
    return {
        "case": f"{kind}-to-rclpy",
        "sent": count if matched_s >= 0 else 0,
        "matched_after_s": round(matched_s, 3),
        **out,
    }


def case_from_rclpy(count: int, env: dict[str, str]) -> dict:
    from cyclonedds.domain import DomainParticipant
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic
    from cyclonedds.util import duration

    from turtlectl.nodes import ros2_types as r

    dp = DomainParticipant(int(env["ROS_DOMAIN_ID"]))
    qos = Qos(Policy.Reliability.Reliable(0), Policy.Durability.Volatile, Policy.History.KeepLast(10), r.XCDR1)
    reader = DataReader(dp, Topic(dp, r.dds_topic("/turtle1/cmd_vel"), r.Twist, qos=qos), qos=qos)
    start = time.monotonic()
    proc = child(env, "rclpy-pub", str(count))
    ready = proc.stdout.readline().strip()
    reader_matched = wait_matched(reader, "get_subscription_matched_status")
    matched_s = time.monotonic() - start
    proc.stdin.write("GO\n")
    proc.stdin.flush()
    latencies, values = [], []
    if ready == "READY":
        for m in reader.take_iter(timeout=duration(seconds=3)):
            latencies.append((time.monotonic() - m.linear.y) * 1e3)
            values.append(m.linear.x)
            if len(values) == count:
                break
    proc.wait(timeout=DEADLINE)
    del reader, dp
    return {
        "case": "twist-from-rclpy",
        "sent": count if ready == "READY" else 0,
        "matched_after_s": round(matched_s, 3),
        "reader_matched": reader_matched >= 0,
        "received": len(values),
        "in_order": values == sorted(values),
        "missing": sorted(set(range(count)) - {int(v) for v in values})[:20],
        **percentiles(latencies),
    }


def case_graph(env: dict[str, str]) -> dict:
    from cyclonedds.domain import DomainParticipant
    from cyclonedds.pub import DataWriter
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.topic import Topic

    from turtlectl.nodes import ros2_types as r

    dp = DomainParticipant(int(env["ROS_DOMAIN_ID"]))
    qos = Qos(Policy.Reliability.Reliable(0), Policy.Durability.Volatile, Policy.History.KeepLast(10), r.XCDR1)
    wanted = {"/turtle1/pose": r.TurtlesimPose, "/odom": r.Odometry, "/clock": r.Clock, "/rosout": r.Log}
    writers = [DataWriter(dp, Topic(dp, r.dds_topic(name), cls, qos=qos), qos=qos) for name, cls in wanted.items()]
    proc = child(env, "rclpy-graph", ",".join(wanted))
    out = json.loads(proc.stdout.readline() or "{}")
    proc.wait(timeout=DEADLINE)
    del writers, dp
    listed = {name: out.get("topics", {}).get(name) for name in wanted}
    return {"case": "graph", "listed": listed, "nodes": out.get("nodes")}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=100)
    parser.add_argument("--no-ignore-type-information", action="store_true")
    parser.add_argument("--case", action="append", help="twist-to-rclpy, scan-to-rclpy, twist-from-rclpy, graph")
    parser.add_argument("--role", nargs="+", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.role:
        role, *rest = args.role
        if role == "rclpy-sub":
            rclpy_sub(rest[0], int(rest[1]))
        elif role == "rclpy-pub":
            rclpy_pub(int(rest[0]))
        else:
            rclpy_graph(rest[0])
        return 0
    if not os.environ.get(NETNS_FLAG):
        if os.geteuid() != 0 or not shutil.which("unshare"):
            print("needs root and unshare: the ROS side runs in a network namespace holding only loopback")
            return 2
        # a fresh network namespace: only lo, brought up; nothing can leave 127.0.0.1
        inner = f"ip link set lo up && exec {sys.executable} {' '.join(map(repr, sys.argv))}"
        env = dict(os.environ, **{NETNS_FLAG: "1"})
        return subprocess.call(["unshare", "--net", "sh", "-c", inner], env=env)
    env = ros_env(not args.no_ignore_type_information)
    os.environ.update(env)  # the Cyclone participant of this process reads CYCLONEDDS_URI
    cases = args.case or ["twist-to-rclpy", "scan-to-rclpy", "twist-from-rclpy", "graph"]
    for case in cases:
        if case == "twist-to-rclpy":
            result = case_to_rclpy("twist", args.count, env)
        elif case == "scan-to-rclpy":
            result = case_to_rclpy("scan", args.count, env)
        elif case == "twist-from-rclpy":
            result = case_from_rclpy(args.count, env)
        else:
            result = case_graph(env)
        result["ignore_type_information"] = not args.no_ignore_type_information
        print(json.dumps(result), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
