"""Cyclone DDS (Python binding) <-> real rclpy (pip wheels, Fast DDS): does a message cross, and how fast?

Not part of `make test` or `make bench` yet: it needs the optional ROS 2 packages in .venv (see
docs/explanation/ros2-dds.md) and root, for a network namespace holding only
loopback (Fast DDS's localhost mode still advertises the network card's address; in the namespace no DDS
packet can leave 127.0.0.1).

    .venv/bin/python bench/ros2_interop.py              # every case, 100 messages each
    .venv/bin/python bench/ros2_interop.py --count 50 --no-ignore-type-information

Cases (each rclpy side is its own process, as a student's node would be):
  twist-to-rclpy   Cyclone writer geometry_msgs/Twist on rt/turtle1/cmd_vel -> rclpy subscription
  scan-to-rclpy    Cyclone writer sensor_msgs/LaserScan (360 ranges) on rt/obstacles -> rclpy subscription
  twist-from-rclpy rclpy publisher /turtle1/cmd_vel -> Cyclone reader
  echo             every ROS type an rclpy wheel provides: Cyclone -> rclpy -> republished -> Cyclone, equal?
  node-names       USER_DATA enclave=/; and a ros_discovery_info sample: rclpy lists the node and its publisher?
  call-service     Cyclone calls an rclpy std_srvs/SetBool service (rq/ and rr/ topics), 5 calls
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


def rclpy_graph(wanted: str, node_name: str = "") -> None:
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
        nodes = [n for n, _ns in node.get_node_names_and_namespaces()]
        if names <= topics.keys() and (not node_name or node_name in nodes):
            break
        rclpy.spin_once(node, timeout_sec=0.1)
    result = {"topics": topics, "nodes": node.get_node_names_and_namespaces()}
    if node_name and node_name in [n for n, _ns in result["nodes"]]:
        result["its_publishers"] = node.get_publisher_names_and_types_by_node(node_name, "/")
    print(json.dumps(result), flush=True)
    node.destroy_node()
    rclpy.shutdown()


def rclpy_echo(pairs: str) -> None:
    """For each ``/topic=pkg/msg/Name``: subscribe with rclpy and publish every message, unchanged, on
    ``/topic_back`` (so the parent checks both directions' encoding of a whole type in one go)."""
    import importlib

    import rclpy
    from rclpy.node import Node

    rclpy.init()
    node = Node("probe_echo")
    keep = []
    for pair in pairs.split(","):
        topic, ros_type = pair.split("=")
        package, _, name = ros_type.split("/")
        cls = getattr(importlib.import_module(f"{package}.msg"), name)
        pub = node.create_publisher(cls, topic + "_back", 10)
        keep.append(node.create_subscription(cls, topic, pub.publish, 10))
    print("READY", flush=True)
    end = time.monotonic() + DEADLINE
    while time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.1)
    node.destroy_node()
    rclpy.shutdown()


def rclpy_server() -> None:
    """Serve std_srvs/SetBool on /set_flag until killed; print each request's data."""
    import rclpy
    from rclpy.node import Node
    from std_srvs.srv import SetBool

    rclpy.init()
    node = Node("probe_server")

    def serve(request, response):
        response.success = request.data
        response.message = f"got {request.data}"
        return response

    node.create_service(SetBool, "/set_flag", serve)
    print("READY", flush=True)
    end = time.monotonic() + DEADLINE
    while time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.1)
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


def echo_samples() -> dict:
    """One sample of each ROS type a pip-installed rclpy can import, values exact in float32."""
    from turtlectl.nodes import ros2_types as r

    stamp = r.Time(sec=1_700_000_000, nanosec=123_456_789)
    return {
        "/turtle1/cmd_vel": r.Twist(linear=r.Vector3(x=1.5, y=-2.0), angular=r.Vector3(z=0.25)),
        "/obstacles": r.LaserScan(
            header=r.Header(stamp=stamp, frame_id="turtle1/base_scan"),
            angle_min=-3.0,
            angle_max=3.0,
            angle_increment=0.5,
            range_min=0.125,
            range_max=4.0,
            ranges=[1.0, float("inf"), 2.5],
            intensities=[0.5],
        ),
        "/odom": r.Odometry(
            header=r.Header(stamp=stamp, frame_id="odom"),
            child_frame_id="turtle1/base_link",
            pose=r.PoseWithCovariance(
                pose=r.Pose(position=r.Point(x=5.5, y=2.0), orientation=r.Quaternion(z=0.6, w=0.8)),
                covariance=[float(i) for i in range(36)],
            ),
            twist=r.TwistWithCovariance(twist=r.Twist(linear=r.Vector3(x=0.3), angular=r.Vector3(z=-0.1))),
        ),
        "/pose2d": r.Pose2D(x=1.0, y=2.0, theta=3.0),
        "/clock": r.Clock(clock=stamp),
        "/rosout": r.Log(stamp=stamp, level=30, name="turtle1.navigator", msg="blocked", file="a.py", line=7),
        "/chatter": r.String(data="hello world"),
    }


def case_echo(env: dict[str, str]) -> dict:
    """Every ROS type of echo_samples: Cyclone writes it, rclpy decodes and republishes it, Cyclone
    reads it back; equal means both directions encode the whole type as rclpy does."""
    from cyclonedds.domain import DomainParticipant
    from cyclonedds.pub import DataWriter
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic
    from cyclonedds.util import duration

    from turtlectl.nodes import ros2_types as r

    samples = echo_samples()
    names = {cls: name for name, cls in r.BY_ROS_NAME.items()}
    pairs = ",".join(f"{topic}={names[type(sample)]}" for topic, sample in samples.items())
    proc = child(env, "rclpy-echo", pairs)
    assert proc.stdout.readline().strip() == "READY"
    dp = DomainParticipant(int(env["ROS_DOMAIN_ID"]))
    qos = Qos(Policy.Reliability.Reliable(0), Policy.Durability.Volatile, Policy.History.KeepLast(10), r.XCDR1)
    results = {}
    for topic, sample in samples.items():
        cls = type(sample)
        writer = DataWriter(dp, Topic(dp, r.dds_topic(topic), cls, qos=qos), qos=qos)
        reader = DataReader(dp, Topic(dp, r.dds_topic(topic + "_back"), cls, qos=qos), qos=qos)
        if wait_matched(writer, "get_publication_matched_status") < 0:
            results[names[cls]] = "writer never matched"
            continue
        if wait_matched(reader, "get_subscription_matched_status") < 0:
            results[names[cls]] = "reader never matched"
            continue
        # rclpy's publisher on _back may not have matched our reader yet (nothing here shows it, and a
        # volatile sample sent before is lost): write again each second until one comes back
        results[names[cls]] = "nothing came back"
        for _attempt in range(5):
            writer.write(sample)
            try:
                back = reader.take_one(timeout=duration(seconds=1))
            except TimeoutError:
                continue
            results[names[cls]] = "equal" if back == sample else f"differs: {back}"
            break
    proc.kill()
    proc.wait()
    return {"case": "echo", "results": results}


def case_node_names(env: dict[str, str], enclave: bool) -> dict:
    """A Cyclone participant that says it holds the node ``bridge_probe`` (USER_DATA ``enclave=/;`` and
    a ``ros_discovery_info`` sample): does rclpy's graph list the node, and its publisher?"""
    from cyclonedds.domain import DomainParticipant
    from cyclonedds.pub import DataWriter
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.topic import Topic

    from turtlectl.nodes import ros2_types as r

    def gid(entity) -> r.Gid:
        return r.Gid(data=list(entity.get_guid().bytes))

    dp = DomainParticipant(int(env["ROS_DOMAIN_ID"]), qos=Qos(Policy.Userdata(b"enclave=/;")) if enclave else None)
    qos = Qos(Policy.Reliability.Reliable(0), Policy.Durability.Volatile, Policy.History.KeepLast(10), r.XCDR1)
    twist = DataWriter(dp, Topic(dp, r.dds_topic("/turtle1/cmd_vel"), r.Twist, qos=qos), qos=qos)
    info_qos = Qos(
        Policy.Reliability.Reliable(0), Policy.Durability.TransientLocal, Policy.History.KeepLast(1), r.XCDR1
    )
    info = DataWriter(dp, Topic(dp, "ros_discovery_info", r.ParticipantEntitiesInfo, qos=info_qos), qos=info_qos)
    node = r.NodeEntitiesInfo(node_namespace="/", node_name="bridge_probe", writer_gid_seq=[gid(twist)])
    info.write(r.ParticipantEntitiesInfo(gid=gid(dp), node_entities_info_seq=[node]))
    proc = child(env, "rclpy-graph", "/turtle1/cmd_vel", "bridge_probe")
    out = json.loads(proc.stdout.readline() or "{}")
    proc.wait(timeout=DEADLINE)
    del twist, info, dp
    return {"case": "node-names" + ("" if enclave else "-no-enclave"), **out}


def case_call_service(env: dict[str, str], calls: int = 5) -> dict:
    """Cyclone as a client of an rclpy service (std_srvs/SetBool on /set_flag): a writer on
    ``rq/set_flagRequest``, a reader on ``rr/set_flagReply``, one call in flight at a time.  Fast DDS
    carries no request header in the payload (the sample identity is RTPS metadata), so the reply is
    matched to its call only by having one call in flight."""
    from dataclasses import dataclass

    from cyclonedds.domain import DomainParticipant
    from cyclonedds.idl import IdlStruct
    from cyclonedds.idl.annotations import final
    from cyclonedds.pub import DataWriter
    from cyclonedds.qos import Policy, Qos
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic
    from cyclonedds.util import duration

    from turtlectl.nodes import ros2_types as r

    @dataclass
    @final
    class SetBoolRequest(IdlStruct, typename="std_srvs::srv::dds_::SetBool_Request_"):
        data: bool = False

    @dataclass
    @final
    class SetBoolResponse(IdlStruct, typename="std_srvs::srv::dds_::SetBool_Response_"):
        success: bool = False
        message: str = ""

    proc = child(env, "rclpy-server")
    assert proc.stdout.readline().strip() == "READY"
    dp = DomainParticipant(int(env["ROS_DOMAIN_ID"]))
    qos = Qos(Policy.Reliability.Reliable(0), Policy.Durability.Volatile, Policy.History.KeepLast(10), r.XCDR1)
    writer = DataWriter(dp, Topic(dp, "rq/set_flagRequest", SetBoolRequest, qos=qos), qos=qos)
    reader = DataReader(dp, Topic(dp, "rr/set_flagReply", SetBoolResponse, qos=qos), qos=qos)
    matched = wait_matched(writer, "get_publication_matched_status") >= 0
    matched = matched and wait_matched(reader, "get_subscription_matched_status") >= 0
    answers, latencies = [], []
    for i in range(calls if matched else 0):
        start = time.monotonic()
        writer.write(SetBoolRequest(data=i % 2 == 0))
        try:
            reply = reader.take_one(timeout=duration(seconds=3))
        except TimeoutError:
            answers.append(None)
            continue
        latencies.append((time.monotonic() - start) * 1e3)
        answers.append([reply.success, reply.message])
    proc.kill()
    proc.wait()
    del writer, reader, dp
    return {"case": "call-service", "matched": matched, "answers": answers, **percentiles(latencies)}


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
        elif role == "rclpy-server":
            rclpy_server()
        elif role == "rclpy-echo":
            rclpy_echo(rest[0])
        else:
            rclpy_graph(*rest)
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
    cases = args.case or [
        "twist-to-rclpy",
        "scan-to-rclpy",
        "twist-from-rclpy",
        "graph",
        "echo",
        "node-names",
        "call-service",
    ]
    for case in cases:
        if case == "twist-to-rclpy":
            result = case_to_rclpy("twist", args.count, env)
        elif case == "scan-to-rclpy":
            result = case_to_rclpy("scan", args.count, env)
        elif case == "twist-from-rclpy":
            result = case_from_rclpy(args.count, env)
        elif case == "echo":
            result = case_echo(env)
        elif case == "call-service":
            result = case_call_service(env)
        elif case in ("node-names", "node-names-no-enclave"):
            result = case_node_names(env, enclave=case == "node-names")
        else:
            result = case_graph(env)
        result["ignore_type_information"] = not args.no_ignore_type_information
        print(json.dumps(result), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
