"""ROS 2 bags, no network: a bag rosbags writes (Twist, turtlesim Pose, LaserScan, Clock, and a type
turtlectl has no counterpart of) read by ``info``'s, ``play``'s and ``plot``'s reader; one that
``record --profile ros2``'s writer makes read by rosbags; bad bags one clear error."""

from __future__ import annotations

import math
from pathlib import Path

import msgspec
import pytest

from turtlectl.cli.recording.bag import RecordingError
from turtlectl.cli.recording.reading import Recording
from turtlectl.messages import Clock, LaserScan, Pose, Twist, encode, encoding_for

pytest.importorskip("rosbags", reason="the ros2 extra (make installs it)")

START = 1_700_000_000_000_000_000


class Inner(msgspec.Struct):
    """A nested field of a user's type (module level: its annotation is resolved here)."""

    a: float


def rosbags_bag(path: Path, twists: int = 20) -> Path:
    """A bag as rosbags writes it (as a ROS user's would be): Twists on /turtle1/cmd_vel at 10 Hz,
    a turtlesim Pose, a LaserScan, a Clock, and std_msgs/String on /chatter."""
    from rosbags.rosbag2 import StoragePlugin, Writer

    from turtlectl.cli.recording.ros2bag import build, typestore

    store = typestore()
    rows = [
        ("/turtle1/cmd_vel", "geometry_msgs/msg/Twist", {"linear": {"x": 1.0}, "angular": {"z": 0.25}}),
        ("/recorded/pose", "turtlesim/msg/Pose", {"x": 2.5, "y": 3.0, "theta": 0.5}),
        (
            "/recorded/scan",
            "sensor_msgs/msg/LaserScan",
            {
                "header": {"stamp": {"sec": 1_700_000_000, "nanosec": 5}, "frame_id": "turtle1/base_scan"},
                "angle_min": -1.0,
                "angle_max": 1.0,
                "angle_increment": 1.0,
                "range_min": 0.1,
                "range_max": 4.0,
                "ranges": [1.0, math.inf, 2.0],
            },
        ),
        ("/clock", "rosgraph_msgs/msg/Clock", {"clock": {"sec": 12, "nanosec": 500}}),
        ("/chatter", "std_msgs/msg/String", {"data": "hello"}),
    ]
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        conns = {t: writer.add_connection(t, ros_type, typestore=store) for t, ros_type, _ in rows}
        for i in range(twists):
            when = START + i * 100_000_000
            for topic, ros_type, fields in rows if i == 0 else rows[:1]:
                writer.write(conns[topic], when, store.serialize_cdr(build(store, ros_type, fields), ros_type))
    return path


@pytest.fixture
def bag(tmp_path: Path) -> Path:
    return rosbags_bag(tmp_path / "bag")


def test_info_lists_a_rosbags_bag_with_its_ros_topics_types_and_counts(bag):
    info = Recording(bag).info()
    got = {t.key: (t.type_name, t.encoding, t.count) for t in info.topics}
    assert got == {
        "/turtle1/cmd_vel": ("geometry_msgs/msg/Twist", "cdr", 20),
        "/recorded/pose": ("turtlesim/msg/Pose", "cdr", 1),
        "/recorded/scan": ("sensor_msgs/msg/LaserScan", "cdr", 1),
        "/clock": ("rosgraph_msgs/msg/Clock", "cdr", 1),
        "/chatter": ("std_msgs/msg/String", "cdr", 1),
    }
    assert info.closed and info.count == 24 and info.duration == pytest.approx(1.9)
    assert Recording(bag / "bag.mcap").info().count == 24  # the MCAP file itself, too


def test_a_rosbags_bag_reads_as_turtlectl_messages_on_keys_and_other_types_as_they_are(bag):
    recording = Recording(bag)
    records = list(recording.records())
    assert recording.unmapped() == {"/chatter": "std_msgs/msg/String"}
    assert {r.key for r in records} == {"turtle1/cmd_vel", "recorded/pose", "recorded/scan", "clock", "/chatter"}
    (chatter,) = [r for r in records if r.key == "/chatter"]  # kept as it is, played as its CDR bytes
    assert (chatter.type_name, chatter.encoding, chatter.message()) == ("", "cdr", None)
    by_key = {r.key: r.message() for r in reversed(records) if r.type_name}  # each key's first
    assert by_key["turtle1/cmd_vel"] == Twist(linear=1.0, angular=0.25, stamp=START)  # no header: when recorded
    assert by_key["recorded/pose"] == Pose(x=2.5, y=3.0, theta=0.5, stamp=START)
    scan = by_key["recorded/scan"]
    assert isinstance(scan, LaserScan) and scan.ranges == [1.0, math.inf, 2.0]
    assert scan.stamp == START + 5 and math.isnan(scan.origin_x)
    assert by_key["clock"] == Clock(clock=12_000_000_500, stamp=12_000_000_500)
    twists = [r for r in records if r.key == "turtle1/cmd_vel"]
    assert [r.log_time for r in twists[:2]] == [START, START + 100_000_000]
    assert twists[0].encoding == encoding_for(Twist)
    assert [r.key for r in recording.records(["turtle1/cmd_vel"])] == ["turtle1/cmd_vel"] * 20


def test_plot_reads_a_rosbags_bag_by_its_keys(bag):
    from turtlectl.cli.tools.plot import Series
    from turtlectl.cli.tools.plot_sources import from_recording

    linear = Series("turtle1/cmd_vel", "linear")
    got = from_recording(bag, [linear])
    times, values = got.collected.xy(linear)
    assert len(times) == 20 and times[-1] == pytest.approx(1.9) and set(values) == {1.0}


def test_a_message_that_does_not_decode_is_one_clear_error(tmp_path):
    from rosbags.rosbag2 import StoragePlugin, Writer

    from turtlectl.cli.recording.ros2bag import typestore

    path = tmp_path / "bad"
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        conn = writer.add_connection("/turtle1/cmd_vel", "geometry_msgs/msg/Twist", typestore=typestore())
        writer.write(conn, START, b"\x00\x01\x00\x00\x01\x02")
    with pytest.raises(
        RecordingError, match="a message on /turtle1/cmd_vel does not decode as geometry_msgs/msg/Twist"
    ):
        list(Recording(path).records())
    assert RecordingError("x").exit_code == 2


def test_a_folder_that_is_no_mcap_bag_is_one_clear_error(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(RecordingError, match="without an MCAP file"):
        Recording(tmp_path / "empty")
    (tmp_path / "split").mkdir()
    for name in ("split_0.mcap", "split_1.mcap"):
        (tmp_path / "split" / name).write_bytes(b"")
    with pytest.raises(RecordingError, match="2 MCAP files"):
        Recording(tmp_path / "split")


def test_the_ros2_writer_makes_a_bag_rosbags_reads_and_leaves_out_what_has_no_ros_type(tmp_path):
    from rosbags.rosbag2 import Reader

    from turtlectl.cli.recording.ros2bag import Ros2BagWriter, typestore
    from turtlectl.messages import Kill

    path = tmp_path / "out"
    writer = Ros2BagWriter(path, "turtlectl test")
    writer.add("turtle1/pose", encoding_for(Pose), encode(Pose(x=1.5, y=2.0, theta=-0.5, seq=3)), START)
    writer.add("turtle1/cmd_vel", encoding_for(Twist), encode(Twist(linear=0.5, angular=1.0)), START + 1)
    writer.add("kill", encoding_for(Kill), encode(Kill(name="turtle2")), START + 2)
    writer.add("kill", encoding_for(Kill), encode(Kill(name="turtle3")), START + 3)
    writer.add("raw", "text/plain", b"hello", START + 4)
    assert writer.notes == [
        "not recorded in the ROS 2 bag: kill (its type turtlectl/Kill has no ROS 2 type here; see docs/how-to/ros2-bags.md)",
        "not recorded in the ROS 2 bag: raw (its payload is no turtlectl message; see docs/how-to/ros2-bags.md)",
    ]
    writer.close()
    assert (writer.messages, writer.raw) == (2, 3)
    store = typestore()
    with Reader(path) as reader:
        assert {c.topic: c.msgtype for c in reader.connections} == {
            "/turtle1/pose": "turtlesim/msg/Pose",
            "/turtle1/cmd_vel": "geometry_msgs/msg/Twist",
        }
        got = [(c.topic, t, store.deserialize_cdr(raw, c.msgtype)) for c, t, raw in reader.messages()]
    assert got[0][1] == START and (got[0][2].x, got[0][2].y, got[0][2].theta) == (1.5, 2.0, -0.5)
    assert (got[1][2].linear.x, got[1][2].angular.z) == (0.5, 1.0)
    # and turtlectl reads its own ROS 2 bag back
    back = [r.message() for r in Recording(path).records()]
    assert back == [Pose(x=1.5, y=2.0, theta=-0.5, stamp=START), Twist(0.5, 1.0, stamp=START + 1)]


def test_the_bag_holds_the_msg_text_and_profile_rosbag2_writes(tmp_path):
    from mcap.reader import make_reader

    from turtlectl.cli.recording.ros2bag import Ros2BagWriter

    path = tmp_path / "out"
    writer = Ros2BagWriter(path)
    scan = LaserScan(angle_min=0, angle_max=1, angle_increment=1, range_min=0, range_max=1, ranges=[1, 1])
    writer.add("obstacles", encoding_for(LaserScan), encode(scan), START)
    writer.close()
    with open(path / "out.mcap", "rb") as f:
        reader = make_reader(f)
        header = reader.get_header()
        summary = reader.get_summary()
    assert header.profile == "ros2"
    (schema,) = summary.schemas.values()
    (channel,) = summary.channels.values()
    assert (schema.name, schema.encoding, channel.message_encoding) == ("sensor_msgs/msg/LaserScan", "ros2msg", "cdr")
    text = schema.data.decode()
    assert text.splitlines()[0].endswith("Header header")
    assert "=" * 80 + "\nMSG: std_msgs/Header\n" in text and "MSG: builtin_interfaces/Time" in text
    qos = channel.metadata["offered_qos_profiles"]
    assert "reliability: reliable" in qos and "durability: volatile" in qos and "depth: 10" in qos


def test_without_rosbags_one_line_says_how_to_install_the_extra(monkeypatch):
    import sys

    from turtlectl.cli.recording.ros2bag import typestore
    from turtlectl.runtime.client.errors import CannotStart

    monkeypatch.setitem(sys.modules, "rosbags.typesys", None)  # as if it were not installed
    with pytest.raises(CannotStart, match=r"pip install 'turtlectl\[ros2\]'") as raised:
        typestore()
    assert raised.value.exit_code == 4
    from typer.testing import CliRunner

    from turtlectl.cli.main import app

    refused = CliRunner().invoke(app, ["record", "-a", "--profile", "ros2", "--connect", "tcp/127.0.0.1:9"])
    assert isinstance(refused.exception, CannotStart)  # before it connects to anything


def test_record_refuses_an_unknown_profile_and_the_scene_in_a_ros2_bag(tmp_path):
    from typer.testing import CliRunner

    from turtlectl.cli.main import app
    from turtlectl.runtime.client.errors import BadInput

    runner = CliRunner()
    wrong = runner.invoke(app, ["record", "-a", "--profile", "ros1", "-o", str(tmp_path / "x")])
    assert isinstance(wrong.exception, BadInput) and wrong.exception.exit_code == 2
    assert str(wrong.exception) == "--profile 'ros1': turtlectl (the default) or ros2"
    scene = runner.invoke(app, ["record", "-a", "--scene", "--profile", "ros2", "-o", str(tmp_path / "x")])
    assert isinstance(scene.exception, BadInput) and "--scene" in str(scene.exception)
    assert not (tmp_path / "x").exists()


def test_a_users_flat_type_is_recorded_as_its_generic_ros_type_and_a_nested_one_is_left_out(tmp_path, monkeypatch):
    from rosbags.rosbag2 import Reader

    from turtlectl.cli.recording.ros2bag import Ros2BagWriter
    from turtlectl.messages import Message, codec

    monkeypatch.setattr(codec, "TYPES_BY_NAME", dict(codec.TYPES_BY_NAME))  # the test's types forgotten after it

    class Reading(Message, tag="bag_test_msgs/Reading"):
        value: float
        count: int
        label: str
        samples: list[float] = msgspec.field(default_factory=list)
        corner: tuple[float, float] = (0.0, 0.0)

    class Nested(Message, tag="bag_test_msgs/Nested"):
        inner: Inner

    for cls in (Reading, Nested):
        codec.register(cls)
    path = tmp_path / "user"
    writer = Ros2BagWriter(path)
    reading = Reading(value=1.5, count=3, label="a", samples=[1.0, 2.0], corner=(0.5, 0.25))
    writer.add("sensor/reading", encoding_for(Reading), encode(reading), START)
    writer.add("sensor/nested", encoding_for(Nested), encode(Nested(inner=Inner(a=1.0))), START + 1)
    writer.close()
    assert writer.notes == [
        "not recorded in the ROS 2 bag: sensor/nested (its type bag_test_msgs/Nested has no ROS 2 type here; "
        "see docs/how-to/ros2-bags.md)"
    ]
    with Reader(path) as reader:
        (connection,) = reader.connections
        assert (connection.topic, connection.msgtype) == ("/sensor/reading", "bag_test_msgs/msg/Reading")
        text = connection.msgdef.data
        assert text.splitlines()[:5] == [
            "float64 value",
            "int64 count",
            "string label",
            "float64[] samples",
            "float64[2] corner",
        ]
        from rosbags.typesys import Stores, get_types_from_msg, get_typestore

        store = get_typestore(Stores.ROS2_KILTED)
        store.register(get_types_from_msg(text, connection.msgtype))
        (raw,) = [raw for _c, _t, raw in reader.messages()]
        got = store.deserialize_cdr(raw, connection.msgtype)
    assert (got.value, got.count, got.label, list(got.samples), list(got.corner)) == (
        1.5,
        3,
        "a",
        [1.0, 2.0],
        [0.5, 0.25],
    )


def test_plot_reads_the_numbers_of_a_ros_type_turtlectl_has_no_type_for(tmp_path):
    from rosbags.rosbag2 import StoragePlugin, Writer

    from turtlectl.cli.recording.ros2bag import build, typestore
    from turtlectl.cli.tools.plot import Series
    from turtlectl.cli.tools.plot_sources import from_recording

    store = typestore()
    path = tmp_path / "odom"
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        conn = writer.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=store)
        for i in range(5):
            odom = build(store, "nav_msgs/msg/Odometry", {"pose": {"pose": {"position": {"x": i / 2}}}})
            writer.write(conn, START + i * 100_000_000, store.serialize_cdr(odom, "nav_msgs/msg/Odometry"))
    x = Series("odom", "pose.pose.position.x")
    times, values = from_recording(path, [x]).collected.xy(x)
    assert times == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4]) and values == [0.0, 0.5, 1.0, 1.5, 2.0]
