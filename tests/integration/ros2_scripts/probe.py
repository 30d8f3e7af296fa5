"""A real rclpy node for the bridge's tests (run with .venv-ros2's python, in the test's namespace).

    probe.py drive LINEAR ANGULAR SECONDS     publish Twist on /turtle1/cmd_vel at 20 Hz once matched
    probe.py listen TOPIC TYPE COUNT [DURABILITY]  print COUNT messages of TYPE on TOPIC as JSON lines (MSG {...});
                                              DURABILITY volatile (default) or transient_local
    probe.py graph TOPICS NODES [NODE]        print rclpy's graph (GRAPH {...}) once it lists them (comma separated),
                                              and what it says NODE publishes and subscribes to
    probe.py talk TOPIC TEXT                  publish std_msgs/String TEXT at 5 Hz until killed
    probe.py latency COUNT                    /turtle1/odom's header stamp to the callback (wall clock), LATENCY {...}
    probe.py odom RATE SECONDS                publish nav_msgs/Odometry on /turtle1/odom at RATE Hz, stamped with
                                              the wall clock (plain rclpy, what the bridge's benchmark compares with)

Each prints READY when its side is set up (a publisher: once a subscription matched).
"""

import importlib
import json
import sys
import time

import rclpy
from rclpy.node import Node

DEADLINE = 30.0


def ros_class(name: str):
    package, _, cls = name.split("/")
    return getattr(importlib.import_module(f"{package}.msg"), cls)


def as_dict(msg) -> dict:
    """A ROS message as plain JSON values."""
    out = {}
    for field in msg.get_fields_and_field_types():
        value = getattr(msg, field)
        if hasattr(value, "get_fields_and_field_types"):
            value = as_dict(value)
        elif hasattr(value, "tolist"):
            value = value.tolist()
        elif isinstance(value, (list, tuple)):
            value = list(value)
        out[field] = value
    return out


def wait_matched(node, pub) -> bool:
    end = time.monotonic() + DEADLINE
    while pub.get_subscription_count() < 1 and time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.05)
    return pub.get_subscription_count() > 0


def drive(node, linear: str, angular: str, seconds: str) -> None:
    from geometry_msgs.msg import Twist

    pub = node.create_publisher(Twist, "/turtle1/cmd_vel", 10)
    print("READY" if wait_matched(node, pub) else "NOMATCH", flush=True)
    msg = Twist()
    msg.linear.x, msg.angular.z = float(linear), float(angular)
    end = time.monotonic() + float(seconds)
    while time.monotonic() < end:
        pub.publish(msg)
        time.sleep(0.05)  # 20 Hz pacing of the commands, not a readiness wait
    print("DONE", flush=True)


def listen(node, topic: str, type_name: str, count: str, durability: str = "volatile") -> None:
    """durability transient_local: as rqt_console and rcl's own /rosout readers ask (keep last 1000)."""
    from rclpy.qos import DurabilityPolicy, QoSProfile

    got = []
    qos = QoSProfile(depth=1000, durability=DurabilityPolicy.TRANSIENT_LOCAL) if durability == "transient_local" else 10
    node.create_subscription(ros_class(type_name), topic, got.append, qos)
    print("READY", flush=True)
    end = time.monotonic() + DEADLINE
    printed = 0
    while printed < int(count) and time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.1)
        while printed < len(got) and printed < int(count):
            print("MSG " + json.dumps(as_dict(got[printed])), flush=True)
            printed += 1


def graph(node, topics: str, nodes: str, inspect: str = "") -> None:
    want_topics = {t for t in topics.split(",") if t}
    want_nodes = {n for n in nodes.split(",") if n}
    print("READY", flush=True)
    end = time.monotonic() + DEADLINE
    while True:
        listed = dict(node.get_topic_names_and_types())
        names = ["/".join(p for p in (ns.strip("/"), n) if p) for n, ns in node.get_node_names_and_namespaces()]
        if (want_topics <= listed.keys() and want_nodes <= set(names)) or time.monotonic() > end:
            break
        rclpy.spin_once(node, timeout_sec=0.1)
    result = {"topics": listed, "nodes": names}
    if inspect:  # what ROS's graph says node INSPECT publishes and subscribes to (ros2 node info)
        ns, _, name = inspect.rpartition("/")
        end = time.monotonic() + DEADLINE
        while time.monotonic() < end:
            pubs = node.get_publisher_names_and_types_by_node(name, "/" + ns)
            subs = node.get_subscriber_names_and_types_by_node(name, "/" + ns)
            if pubs and subs:
                break
            rclpy.spin_once(node, timeout_sec=0.1)
        result["publishers"], result["subscribers"] = dict(pubs), dict(subs)
    print("GRAPH " + json.dumps(result), flush=True)


def talk(node, topic: str, text: str) -> None:
    from std_msgs.msg import String

    pub = node.create_publisher(String, topic, 10)
    print("READY" if wait_matched(node, pub) else "NOMATCH", flush=True)
    msg = String()
    msg.data = text
    end = time.monotonic() + DEADLINE
    while time.monotonic() < end:
        pub.publish(msg)
        time.sleep(0.2)  # 5 Hz pacing


def latency(node, count: str) -> None:
    """How long after turtlectl stamped a pose its odometry reaches this callback (ms: p50, p90, max)."""
    from nav_msgs.msg import Odometry

    delays = []

    def on_odom(msg) -> None:
        stamp = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        delays.append((time.time_ns() - stamp) / 1e6)

    node.create_subscription(Odometry, "/turtle1/odom", on_odom, 10)
    print("READY", flush=True)
    end = time.monotonic() + DEADLINE + int(count) / 50
    while len(delays) < int(count) + 20 and time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.1)
    kept = sorted(delays[20:])  # the first ones may be from before the match settled
    result = {"count": len(kept)}
    if kept:
        result.update(
            p50_ms=round(kept[len(kept) // 2], 3),
            p90_ms=round(kept[int(0.9 * (len(kept) - 1))], 3),
            max_ms=round(kept[-1], 3),
        )
    print("LATENCY " + json.dumps(result), flush=True)


def odom(node, rate: str, seconds: str) -> None:
    from nav_msgs.msg import Odometry

    pub = node.create_publisher(Odometry, "/turtle1/odom", 10)
    print("READY", flush=True)
    period, end = 1.0 / float(rate), time.monotonic() + float(seconds)
    due = time.monotonic()
    while time.monotonic() < end:
        msg = Odometry()
        msg.header.frame_id, msg.child_frame_id = "odom", "turtle1/base_link"
        now = time.time_ns()
        msg.header.stamp.sec, msg.header.stamp.nanosec = now // 1_000_000_000, now % 1_000_000_000
        msg.pose.pose.position.x = 5.5
        pub.publish(msg)
        due += period
        time.sleep(max(0.0, due - time.monotonic()))  # the publishing rate's pacing


def main() -> None:
    mode, *args = sys.argv[1:]
    rclpy.init()
    node = Node(f"probe_{mode}")
    try:
        {"drive": drive, "listen": listen, "graph": graph, "talk": talk, "latency": latency, "odom": odom}[mode](
            node, *args
        )
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
