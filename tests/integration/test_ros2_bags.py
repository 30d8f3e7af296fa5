"""ROS 2 bags against the real system, no DDS: ``record --profile ros2`` writes a bag that the rosbags
library reads message for message (each equal to what was published, as a subscriber saw it in the
same run), and a bag written by rosbags plays into a launched system (its Twists drive the turtle;
info and plot read it)."""

from __future__ import annotations

import collections
import math
import signal
import subprocess
import time
from pathlib import Path

import pytest

from tests.integration.harness import running_system, turtlectl
from turtlectl.messages import Message, decode_any

pytestmark = pytest.mark.integration

rosbags = pytest.importorskip("rosbags", reason="the ros2 extra (make installs it)")

MAPPED = ("turtle1/pose", "robot/status", "obstacles", "turtle1/cmd_vel", "clock")


def _wait(condition, what: str, timeout: float = 15.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.05)  # pacing: polling a file under a deadline


def _bytes_of(store, message: Message, key: str) -> bytes:
    from turtlectl.cli.recording.ros2bag import build
    from turtlectl.nodes.ros2_fields import to_ros

    converted = to_ros(message, key)
    assert converted is not None, (key, message)
    ros_type, fields = converted
    return bytes(store.serialize_cdr(build(store, ros_type, fields), ros_type))


def _contiguous(part: list[bytes], whole: list[bytes]) -> bool:
    n = len(part)
    return any(whole[i : i + n] == part for i in range(len(whole) - n + 1))


def test_a_ros2_recording_reads_in_rosbags_message_for_message(tmp_path: Path):
    from rosbags.rosbag2 import Reader

    from turtlectl.cli.recording.ros2bag import typestore
    from turtlectl.nodes.ros2_fields import from_ros, to_ros
    from turtlectl.nodes.ros2_profile import ros_topic

    bag = tmp_path / "run_bag"
    with running_system() as system:
        seen: dict[str, list[Message]] = collections.defaultdict(list)
        sub = system.session.declare_subscriber(
            "**", lambda s: seen[str(s.key_expr)].append(decode_any(s.payload.to_bytes()))
        )
        recorder = subprocess.Popen(
            [*turtlectl(), "record", "-a", "--profile", "ros2", "-o", str(bag), "--connect", system.endpoint],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            stdin=subprocess.DEVNULL,
            text=True,
        )
        try:
            _wait(lambda: (bag / f"{bag.name}.mcap").exists(), "the recorder to open its bag")
            _wait(lambda: len(seen["turtle1/pose"]) > 150, "poses")
            response, _, _ = system.navigate(6.5, 5.5, 0.0)
            assert response.success, response
            recorder.send_signal(signal.SIGINT)
            out, err = recorder.communicate(timeout=15)
        finally:
            if recorder.poll() is None:
                recorder.kill()
        time.sleep(0.3)  # noqa: TID251 - pacing: the subscriber sees what arrived after the recorder stopped
        sub.undeclare()
    assert recorder.returncode == 0, err
    assert "recorded" in out
    # what has no ROS 2 type is said once per topic: the goal's feedback
    assert err.count("not recorded in the ROS 2 bag: navigate_to/feedback (its type turtlectl/NavigateToFeedback") == 1
    assert sorted(p.name for p in bag.iterdir()) == ["metadata.yaml", f"{bag.name}.mcap"]

    store = typestore()
    got: dict[str, list[bytes]] = collections.defaultdict(list)
    types = {}
    with Reader(bag) as reader:
        for connection in reader.connections:
            types[connection.topic] = connection.msgtype
            assert connection.ext.serialization_format == "cdr"
            assert connection.ext.offered_qos_profiles, connection.topic
        for connection, _t, raw in reader.messages():
            got[connection.topic].append(bytes(raw))
            types.setdefault(connection.topic, connection.msgtype)
            message = store.deserialize_cdr(raw, connection.msgtype)
            assert from_ros(connection.msgtype, message) is not None
    assert types["/turtle1/cmd_vel"] == "geometry_msgs/msg/Twist"
    assert types["/turtle1/pose"] == "turtlesim/msg/Pose"
    assert types["/obstacles"] == "sensor_msgs/msg/LaserScan"
    assert types["/robot/status"] == "capstone_msgs/msg/TurtleStatus"
    assert types["/clock"] == "rosgraph_msgs/msg/Clock"
    for key in MAPPED:
        if key != "clock":  # only a system on simulated time publishes it
            assert len(got["/" + key]) > 5, key
    # every topic of the bag (the logs' too), message for message, a run of what was published on its key
    keys = {ros_topic(k): k for k, messages in seen.items() if messages and to_ros(messages[0], k) is not None}
    assert set(got) <= set(keys), set(got) - set(keys)
    for topic, recorded in got.items():
        key = keys[topic]
        expected = [_bytes_of(store, m, key) for m in seen[key]]
        assert _contiguous(recorded, expected), f"{key}: {len(recorded)} recorded, not a run of what was published"
    # independent of turtlectl's own serializer: rosbags' values are the published ones
    poses = [store.deserialize_cdr(raw, "turtlesim/msg/Pose") for raw in got["/turtle1/pose"]]
    published = [(m.x, m.y) for m in seen["turtle1/pose"]]
    assert all(any(abs(p.x - x) < 1e-5 and abs(p.y - y) < 1e-5 for x, y in published) for p in poses)  # float32
    assert any(math.hypot(p.x - 6.5, p.y - 5.5) < 0.3 for p in poses)


def test_a_bag_written_by_rosbags_drives_the_turtle_and_info_and_plot_read_it(tmp_path: Path):
    from tests.unit.cli.recording.test_ros2bag import rosbags_bag

    bag = rosbags_bag(tmp_path / "student_bag", twists=20)  # 2 s of linear 1.0 m/s, angular 0.25 rad/s
    with running_system() as system:
        info = subprocess.run([*turtlectl(), "info", str(bag)], capture_output=True, text=True, timeout=30)
        assert info.returncode == 0, info.stderr
        assert "/turtle1/cmd_vel" in info.stdout and "geometry_msgs/msg/Twist" in info.stdout
        assert "std_msgs/msg/String" in info.stdout
        png = tmp_path / "linear.png"
        plotted = subprocess.run(
            [*turtlectl(), "plot", "turtle1/cmd_vel.linear", "-i", str(bag), "-o", str(png)],
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert plotted.returncode == 0, plotted.stderr
        assert png.read_bytes().startswith(b"\x89PNG")

        before = system.latest_pose()
        played = system.run_cli("play", str(bag))
        assert played.returncode == 0, played.stderr
        assert "played 24 messages" in played.stdout
        assert played.stderr.count("\n") == 1
        assert "/chatter: std_msgs/msg/String has no turtlectl type: played as its CDR bytes" in played.stderr
        after = system.wait_stopped(timeout=5.0)
        moved = math.hypot(after.x - before.x, after.y - before.y)
        turned = (after.theta - before.theta) % (2 * math.pi)
        # 2 s of Twists, and the last one held until the simulator's command timeout
        assert 1.5 < moved < 3.5, (before, after)  # at 1 m/s
        assert 0.35 < turned < 0.9, (before, after)  # at 0.25 rad/s
