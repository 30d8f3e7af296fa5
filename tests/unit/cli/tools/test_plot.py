"""cli.tools.plot, the model of `turtlectl plot`: KEY.FIELD as typed, the number a
message holds there (and what is said when it holds none), the live plot's sliding window and
its status line; cli.tools.plot_draw's chart and pictures, and a recording read whole
(cli.tools.plot_sources.from_recording), all without a system."""

from __future__ import annotations

import math
import struct
from pathlib import Path

import msgspec
import pytest

from turtlectl.cli.tools import plot, plot_window
from turtlectl.cli.tools.format import Undescribed
from turtlectl.cli.tools.plot import Extractor, Series, parse_series
from turtlectl.cli.tools.plot_window import Collected, Window
from turtlectl.messages import LaserScan, NavigateToFeedback, Pose, TurtleStatus, encode, encoding_for
from turtlectl.runtime.client.errors import BadInput, Unreachable

POSE_NUMBERS = "x, y, theta, linear_velocity, angular_velocity, contact, stamp, seq"


def status(battery: float, **fields) -> TurtleStatus:
    return TurtleStatus(x=1.0, y=2.0, theta=0.0, vel_x=0.0, vel_y=0.0, battery=battery, **fields)


def feedback(**fields) -> NavigateToFeedback:
    return NavigateToFeedback(
        state="driving",
        distance_remaining=2.0,
        heading_remaining=0.0,
        eta=1.0,
        elapsed=0.5,
        x=1,
        y=2,
        theta=0,
        **fields,
    )


# -- KEY.FIELD ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "text, key, path",
    [
        ("robot/status.battery", "robot/status", "battery"),
        ("turtle1/pose.x", "turtle1/pose", "x"),
        ("/turtle1/pose.x", "turtle1/pose", "x"),  # ROS's leading slash
        ("obstacles.ranges.0", "obstacles", "ranges.0"),  # a list's item
        ("navigate_to/feedback.path.0.1", "navigate_to/feedback", "path.0.1"),  # nested
        ("my.robot/odom.twist.linear", "my.robot/odom", "twist.linear"),  # a '.' before the last chunk is the key's
    ],
)
def test_the_field_starts_at_the_first_dot_of_the_keys_last_chunk(text, key, path):
    assert parse_series(text) == Series(key, path)
    assert parse_series(text).label == f"{key}.{path}"


def test_with_a_turtle_the_key_is_that_turtles_as_echo_resolves_it():
    assert parse_series("robot/status.battery", "turtle2").label == "turtle2/robot/status.battery"
    assert parse_series("turtle1/pose.x", "turtle2").label == "turtle2/pose.x"
    assert parse_series("/chatter.data", "turtle2").label == "chatter.data"  # absolute


@pytest.mark.parametrize(
    "text, said",
    [
        ("turtle1/pose/x", "'turtle1/pose/x': name a field after the key and a '.', as turtle1/pose.x (KEY.FIELD)"),
        ("/turtle2/pose/x", "'/turtle2/pose/x': name a field after the key and a '.', as /turtle2/pose.x (KEY.FIELD)"),
        ("turtle3/pose/theta", "'turtle3/pose/theta': name a field after the key and a '.', as turtle3/pose.theta"),
        (
            "turtle2/robot/status/battery",
            "'turtle2/robot/status/battery': name a field after the key and a '.', as turtle2/robot/status.battery",
        ),
        ("robot/status", "'robot/status': name a field after the key and a '.', as robot/status.battery (KEY.FIELD)"),
        (".x", "'.x': write KEY.FIELD, as robot/status.battery or turtle1/pose.x"),
        ("turtle1/pose.", "'turtle1/pose.': write KEY.FIELD, as robot/status.battery or turtle1/pose.x"),
        ("robot/status.a..b", "'robot/status.a..b': the field 'a..b' has an empty part"),
        ("turtle1/*.x", "'turtle1/*.x': plot one plain key per series (no wildcards"),
        ("**/pose.x", "'**/pose.x': plot one plain key per series"),
        ("@turtlectl/x.y", "'@turtlectl/x.y': plot one plain key per series"),
    ],
)
def test_what_is_no_key_and_field_says_how_to_write_one(text, said):
    with pytest.raises(BadInput) as raised:
        parse_series(text)
    assert raised.value.message.startswith(said)


def test_each_series_once_in_the_order_typed():
    assert [s.label for s in plot.parse_all(["turtle1/pose.x", "robot/status.battery", "/turtle1/pose.x"])] == [
        "turtle1/pose.x",
        "robot/status.battery",
    ]


# -- numbers -----------------------------------------------------------------------------------


def test_numbers_and_bools_are_plotted_text_and_lists_are_not():
    assert plot.number(3) == 3.0 and plot.number(2.5) == 2.5
    assert plot.number(True) == 1.0 and plot.number(False) == 0.0
    assert plot.number("driving") is None and plot.number([1.0]) is None and plot.number(None) is None


def test_the_first_message_of_a_series_must_have_a_number_there():
    extractor = Extractor([Series("turtle1/pose", "z")])
    with pytest.raises(BadInput) as raised:
        extractor.values("turtle1/pose", Pose(x=1, y=2, theta=0))
    assert (
        raised.value.message
        == f"turtle1/pose.z: turtlectl/Pose has no field 'z'; the numeric fields of turtlectl/Pose: {POSE_NUMBERS}"
    )


@pytest.mark.parametrize(
    "path, why",
    [
        ("state", "state is text ('driving'), not a number"),
        ("path", "path is a list of 1: plot one of its items, as navigate_to/feedback.path.0"),
        ("path.0", "path.0 is a list of 2: plot one of its items, as navigate_to/feedback.path.0.0"),
    ],
)
def test_a_field_that_is_no_number_names_the_numeric_fields_of_its_type(path, why):
    with pytest.raises(BadInput) as raised:
        Extractor([Series("navigate_to/feedback", path)]).values("navigate_to/feedback", feedback(path=[(1.0, 2.0)]))
    assert raised.value.message == (
        f"navigate_to/feedback.{path}: {why}; the numeric fields of turtlectl/NavigateToFeedback: distance_remaining, "
        "heading_remaining, eta, elapsed, x, y, theta, goal_x, goal_y, goal_theta, scan_stale, path.N.0, path.N.1, "
        "replans, stamp, seq"
    )


def test_after_the_first_a_message_without_the_number_is_left_out():
    """A list that is shorter this time (a path re-planned) is no error once the series has plotted."""
    series = Series("navigate_to/feedback", "path.1.0")
    extractor = Extractor([series])
    assert extractor.values("navigate_to/feedback", feedback(path=[(0.0, 0.0), (3.0, 4.0)])) == [(series, 3.0)]
    assert extractor.values("navigate_to/feedback", feedback(path=[(0.0, 0.0)])) == []
    assert extractor.values("navigate_to/feedback", feedback(path=[(0.0, 0.0), (5.0, 4.0)])) == [(series, 5.0)]


def test_inf_and_nan_are_no_sample_and_no_error():
    ranges = [math.inf, 2.0, math.nan]
    scan = LaserScan(angle_min=0, angle_max=1, angle_increment=0.5, range_min=0.1, range_max=5, ranges=ranges)
    first, second, third = (Series("obstacles", f"ranges.{i}") for i in range(3))
    extractor = Extractor([first, second, third])
    assert extractor.values("obstacles", scan) == [(second, 2.0)]
    assert extractor.values("obstacles", scan) == [(second, 2.0)]
    assert extractor.values("obstacles", LaserScan(**{**msgspec.structs.asdict(scan), "ranges": [1.0]})) == [
        (first, 1.0)
    ]


def test_one_message_gives_every_series_on_its_key_bools_as_0_or_1():
    x, contact, battery = (
        Series("turtle1/pose", "x"),
        Series("turtle1/pose", "contact"),
        Series("robot/status", "battery"),
    )
    extractor = Extractor([x, contact, battery])
    assert extractor.values("turtle1/pose", Pose(x=4.5, y=2, theta=0, contact=True)) == [(x, 4.5), (contact, 1.0)]
    assert extractor.values("robot/status", status(88.0)) == [(battery, 88.0)]
    assert extractor.values("turtle2/pose", Pose(x=1, y=1, theta=0)) == []


def test_an_undescribed_payload_is_read_as_the_data_it_is():
    data = Undescribed({"type": "Odometry", "twist": {"linear": [0.5, 0.0]}, "frame": "odom"}, "Odometry")
    linear = Series("odom", "twist.linear.0")
    assert Extractor([linear]).values("odom", data) == [(linear, 0.5)]
    with pytest.raises(BadInput) as raised:
        Extractor([Series("odom", "frame")]).values("odom", data)
    assert raised.value.message == (
        "odom.frame: frame is text ('odom'), not a number; the numeric fields of Odometry: twist.linear.N"
    )


def test_a_described_type_whose_own_field_is_named_data_is_read_as_itself():
    from turtlectl.messages import Message

    class Float64(Message, tag="PlotFloat64WithData"):  # a user's own type (std_msgs' Float64)
        data: float = 0.0
        stamp: int = 0

    chatter = Series("chatter", "data")
    assert Extractor([chatter]).values("chatter", Float64(data=2.5)) == [(chatter, 2.5)]
    stamps = plot.Stamps()
    assert stamps.time("chatter", Float64(data=1.0, stamp=START)) == 0.0
    assert stamps.time("chatter", Float64(data=1.0, stamp=START + 1_500_000_000)) == pytest.approx(1.5)


# -- a type known before any message -----------------------------------------------------------


@pytest.mark.parametrize("path", ["x", "contact", "seq"])
def test_a_numeric_field_of_a_known_type_passes(path):
    plot.check_type(Series("turtle1/pose", path), Pose)


@pytest.mark.parametrize("path", ["ranges.0", "ranges.359", "ranges.-1", "range_max"])
def test_a_list_item_of_a_known_type_passes_whatever_its_index(path):
    plot.check_type(Series("obstacles", path), LaserScan)


@pytest.mark.parametrize(
    "msg_type, path, why",
    [
        (Pose, "z", "turtlectl/Pose has no field 'z'"),
        (LaserScan, "ranges", "ranges holds several values: plot one number of it, as k.ranges.0"),
        (NavigateToFeedback, "path.2", "path.2 holds several values: plot one number of it, as k.path.0.0"),
        (NavigateToFeedback, "state", "state is not a number"),
        (Pose, "x.y", "x.y is not a number"),
    ],
)
def test_a_known_type_says_before_any_message_what_is_no_number(msg_type, path, why):
    with pytest.raises(BadInput) as raised:
        plot.check_type(Series("k", path), msg_type)
    assert raised.value.message.startswith(f"k.{path}: {why}; the numeric fields of turtlectl/{msg_type.__name__}: ")


def test_the_built_in_keys_types_are_known_for_any_turtle():
    assert plot.builtin_type("robot/status") is TurtleStatus
    assert plot.builtin_type("turtle2/robot/status", "turtle2") is TurtleStatus
    assert plot.builtin_type("turtle2/pose", "turtle2") is Pose
    assert plot.builtin_type("odom") is None


# -- the sliding window ------------------------------------------------------------------------


def test_the_window_keeps_the_last_seconds_and_one_sample_before_them():
    s = Series("robot/status", "battery")
    window = Window([s], 10.0)
    assert window.x_limits() == (0.0, 10.0) and window.y_limits() is None
    for t in range(25):
        window.add(s, float(t), 100.0 - t)
        window.advance(float(t))
    assert window.x_limits() == (14.0, 24.0)
    times, values = window.xy(s)
    assert times == [float(t) for t in range(14, 25)] and values[-1] == 76.0  # 14: the edge itself
    window.advance(24.5)
    assert window.xy(s)[0][0] == 14.0  # the last sample before the window comes in from the left edge
    assert window.latest[s] == 76.0


def test_the_value_axis_has_room_for_what_the_window_shows():
    s = Series("turtle1/pose", "x")
    window = Window([s], 5.0)
    for t, x in [(0.0, 100.0), (1.0, 2.0), (6.5, 4.0), (7.0, 6.0)]:
        window.add(s, t, x)
    window.advance(7.0)
    assert window.y_limits() == pytest.approx((3.9, 6.1))  # 100 and 2 left the window: 4..6 and 5 % each side
    assert plot_window.value_limits([100.0, 100.0]) == (99.0, 101.0)  # a constant: a line, not the frame
    assert plot_window.value_limits([]) is None


def test_the_status_line_has_each_latest_number_or_that_it_waits():
    x, battery = Series("turtle1/pose", "x"), Series("robot/status", "battery")
    window = Window([x, battery], 10.0)
    assert plot_window.status_line(window, 100) == "turtle1/pose.x (waiting)  robot/status.battery (waiting) | q quits"
    window.add(x, 0.5, 5.544449)
    assert plot_window.status_line(window, 100) == "turtle1/pose.x 5.54445  robot/status.battery (waiting) | q quits"
    assert plot_window.status_line(window, 20) == "turtle1/pose.x 5.54"  # width - 1: never the last column


def test_collected_samples_count_and_say_which_series_has_none():
    x, y = Series("turtle1/pose", "x"), Series("turtle1/pose", "y")
    collected = Collected([x, y])
    collected.add(x, 1.0, 2.0)
    collected.add(x, 3.5, 2.0)
    assert collected.count == 2 and collected.empty() == [y] and collected.span() == 2.5
    assert collected.xy(x) == ([1.0, 3.5], [2.0, 2.0])


# -- pictures ----------------------------------------------------------------------------------


@pytest.mark.parametrize("name, kind", [("a.png", "png"), ("b.SVG", "svg"), ("dir.v2/c.svg", "svg")])
def test_a_picture_is_a_png_or_an_svg(name, kind):
    assert plot.picture_format(Path(name)) == kind


@pytest.mark.parametrize(
    "name, said",
    [
        ("a.jpg", "--output 'a.jpg': write a .png or .svg file ('.jpg' is neither)"),
        ("plot", "--output 'plot': write a .png or .svg file (no extension is neither)"),
    ],
)
def test_any_other_picture_is_bad_input(name, said):
    with pytest.raises(BadInput) as raised:
        plot.picture_format(Path(name))
    assert raised.value.message == said


LINES = [("robot/status.battery", [0.0, 1.0, 2.0], [100.0, 99.5, 99.0]), ("turtle1/pose.x", [0.5, 1.5], [5.5, 6.0])]


def png_size(path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def test_a_png_and_an_svg_are_written_with_the_series_labels(tmp_path):
    from turtlectl.cli.tools import plot_draw

    plot_draw.write_picture(tmp_path / "out.png", "png", LINES, "run.mcap")
    assert png_size(tmp_path / "out.png") == (1000, 500)
    plot_draw.write_picture(tmp_path / "out.svg", "svg", LINES, "run.mcap")
    svg = (tmp_path / "out.svg").read_text()
    assert svg.lstrip().startswith("<?xml") and "<svg" in svg
    assert all(label in svg for label in ("robot/status.battery", "turtle1/pose.x", "time (s)", "run.mcap"))


def test_a_picture_that_cannot_be_written_is_bad_input(tmp_path):
    from turtlectl.cli.tools import plot_draw

    with pytest.raises(BadInput) as raised:
        plot_draw.write_picture(tmp_path / "no" / "out.png", "png", LINES, "t")
    assert raised.value.message.startswith(f"cannot write {tmp_path / 'no' / 'out.png'}: ")


def test_the_terminal_chart_has_a_legend_line_the_plot_and_the_time_axis():
    from turtlectl.cli.tools import plot_draw

    lines = plot_draw.chart(LINES, 80, 20, (0.0, 10.0), (98.0, 101.0), color=False)
    assert len(lines) == 20 and all(len(line) <= 80 for line in lines)
    assert lines[0].split() == ["━━", "robot/status.battery", "━━", "turtle1/pose.x"]
    assert "time (s)" in lines[-1] and "10.0" in lines[-2] and "\x1b" not in "".join(lines)
    assert any(set(line) & set("⠁⠂⠄⡀⢀⠈⠐⠠⣀⠉⠒⠤") for line in lines[2:-3])  # braille dots: the lines drawn
    colored = plot_draw.chart(LINES, 80, 20, color=True)
    assert "\x1b[38;5;12m━━\x1b[0m robot/status.battery" in colored[0]


def test_the_legend_is_cut_to_the_width():
    from turtlectl.cli.tools import plot_draw

    assert plot_draw.legend(LINES, 30, color=False) == "━━ robot/status.battery   ━━ t"
    assert plot_draw.legend(LINES, 30, color=True).endswith("\x1b[0m t")
    assert plot_draw.legend(LINES, 28, color=False) == "━━ robot/status.battery"  # no mark without a label
    assert plot_draw.legend(LINES, 10, color=False) == "━━ robot/s"


# -- a recording, read whole -------------------------------------------------------------------

START = 1_700_000_000_000_000_000


@pytest.fixture
def recording(tmp_path):
    from turtlectl.cli.recording.bag import BagWriter

    path = tmp_path / "run.mcap"
    writer = BagWriter(path)
    writer.add("turtle1/cmd_vel", "application/octet-stream", b"\x00garbage", START)  # the recording's start
    for i in range(50):
        t = START + 100_000_000 + i * 20_000_000
        writer.add("turtle1/pose", encoding_for(Pose), encode(Pose(x=i / 10, y=5, theta=0, seq=i)), t)
        if i % 10 == 0:
            writer.add("robot/status", encoding_for(TurtleStatus), encode(status(100 - i / 10)), t)
    writer.close()
    return path


def test_a_recording_is_read_whole_on_its_own_time(recording):
    from turtlectl.cli.tools.plot_sources import from_recording

    x, battery = Series("turtle1/pose", "x"), Series("robot/status", "battery")
    got = from_recording(recording, [x, battery])
    assert got.closed and got.duration == pytest.approx(1.08)
    times, values = got.collected.xy(x)
    assert len(times) == 50 and times[0] == pytest.approx(0.1) and times[-1] == pytest.approx(1.08)
    assert values[:3] == [0.0, 0.1, 0.2]
    assert got.collected.xy(battery) == (pytest.approx([0.1, 0.3, 0.5, 0.7, 0.9]), [100.0, 99.0, 98.0, 97.0, 96.0])


def test_a_key_the_recording_does_not_hold_is_nothing_to_plot(recording):
    from turtlectl.cli.tools.plot_sources import from_recording

    with pytest.raises(Unreachable) as raised:
        from_recording(recording, [Series("turtle1/pose", "x"), Series("obstacles", "ranges.0")])
    assert raised.value.message == (
        f"{recording} has no messages on obstacles (it holds robot/status, turtle1/cmd_vel, turtle1/pose)"
    )


def test_a_field_the_recorded_type_has_no_number_at_is_bad_input(recording):
    from turtlectl.cli.tools.plot_sources import from_recording

    with pytest.raises(BadInput) as raised:
        from_recording(recording, [Series("turtle1/pose", "heading")])
    assert raised.value.message == (
        f"turtle1/pose.heading: turtlectl/Pose has no field 'heading'; the numeric fields of turtlectl/Pose: {POSE_NUMBERS}"
    )


def test_a_raw_payload_that_is_no_data_gives_no_number(recording):
    from turtlectl.cli.tools.plot_sources import from_recording

    with pytest.raises(Unreachable) as raised:
        from_recording(recording, [Series("turtle1/cmd_vel", "linear")])
    assert raised.value.message == (
        f"{recording}: no number to plot in turtle1/cmd_vel.linear (only inf or NaN, or payloads that are no message)"
    )


# -- what a new user meets -----------------------------------------------------------------------


def scan(count: int, stamp: int = 0) -> LaserScan:
    return LaserScan(
        angle_min=0, angle_max=1, angle_increment=0.1, range_min=0.1, range_max=5, ranges=[1.0] * count, stamp=stamp
    )


def test_an_index_past_the_end_of_the_first_message_says_so():
    with pytest.raises(BadInput) as raised:
        Extractor([Series("obstacles", "ranges.999")]).values("obstacles", scan(72))
    assert raised.value.message == (
        "obstacles.ranges.999: obstacles.ranges has 72 items in the first turtlectl/LaserScan; ranges.999 is past the end "
        "(ranges.-1 is the last)"
    )


def test_the_status_line_keeps_each_series_slot_and_a_silent_keys_short_reason():
    x, here = Series("turtle1/pose", "x"), Series("nobody/here", "x")
    window = Window([x, here], 10.0)
    window.add(x, 0.5, 3.0)
    silent = {
        "nobody/here": "nothing published on nobody/here yet: no running node publishes it (`turtlectl list` shows the topics)"
    }
    assert plot_window.status_line(window, 200, silent) == (
        "turtle1/pose.x 3  nobody/here.x (silent: no running node publishes it) | q quits"
    )
    window.add(here, 1.0, 2.0)
    stalled = {
        "nobody/here": "nothing published on nobody/here for 3 s although sim publishes it: it may be stalled (see its log)"
    }
    assert plot_window.status_line(window, 200, stalled, quits=False) == (
        "turtle1/pose.x 3  nobody/here.x 2 (silent for 3 s although sim publishes it)"
    )
    lost = "no router at tcp/x:1: waiting for it (is `turtlectl launch` running?)"
    assert plot_window.status_line(window, 200, {}, lost).startswith(
        "no router at tcp/x:1: waiting for it | turtle1/pose.x 3"
    )


def test_a_key_that_is_no_known_one_gets_the_nearest_known_key():
    assert plot.nearest_key("turtle1/pos") == "turtle1/pose"
    assert plot.nearest_key("turtle2/pos", "turtle2") == "turtle2/pose"
    assert plot.nearest_key("turtle1/pose") is None  # known
    assert plot.nearest_key("my_robot/odometry") is None  # nothing near


def test_with_stamps_the_time_is_each_messages_stamp_from_the_first():
    stamps = plot.Stamps()
    assert stamps.time("obstacles", scan(1, START + 2_000_000_000)) == 0.0
    assert stamps.time("obstacles", scan(1, START + 4_300_000_000)) == pytest.approx(2.3)
    assert stamps.time("obstacles", scan(1, 0)) is None  # not stamped: no sample
    with pytest.raises(BadInput) as raised:
        stamps.time("odom", Undescribed({"type": "Odometry", "x": 1.0}, "Odometry"))
    assert raised.value.message.startswith("--stamps: Odometry on odom has no stamp")


def test_with_stamps_a_known_type_without_one_is_bad_input_at_once():
    from turtlectl.messages import Message
    from turtlectl.messages.keys import CLOCK

    class Odometry(Message, tag="OdometryWithoutStamp"):
        x: float = 0.0

    plot.check_builtins([Series("turtle1/pose", "x"), Series(CLOCK, "clock")], stamps=True)  # every built-in is stamped
    with pytest.raises(BadInput) as raised:  # a recording's type without one
        plot.check_builtins([Series("turtle1/pose", "x")], stamps=True, types={"odom": Odometry})
    # the type by its full name, the one on the wire (not the Python class's)
    assert raised.value.message.startswith("--stamps: tests/OdometryWithoutStamp on odom has no stamp")


def test_a_recording_is_plotted_on_its_stamps_with_stamps(tmp_path):
    from turtlectl.cli.recording.bag import BagWriter
    from turtlectl.cli.tools.plot_sources import from_recording

    path = tmp_path / "sim.mcap"
    writer = BagWriter(path)
    for i in range(24):  # logged 0.1 s apart on the wall clock, stamped 0.5 s apart (5 x simulated time)
        pose = encode(Pose(x=i, y=0, theta=0, stamp=START + i * 500_000_000))
        writer.add("turtle1/pose", encoding_for(Pose), pose, START + i * 100_000_000)
    writer.close()
    x = Series("turtle1/pose", "x")
    assert from_recording(path, [x]).duration == pytest.approx(2.3)
    got = from_recording(path, [x], stamps=True)
    assert got.duration == pytest.approx(11.5) and got.collected.xy(x)[0][-1] == pytest.approx(11.5)


def test_a_typo_in_a_key_nobody_publishes_is_said_with_the_nearest_known_key():
    from turtlectl.cli.tools.plot_sources import typo_notes
    from turtlectl.runtime.client.graph import build_graph

    empty = build_graph([], 0)
    assert typo_notes(empty, [Series("turtle1/pos", "x"), Series("turtle1/pose", "y")]) == {
        "turtle1/pos": "nothing publishes turtle1/pos: did you mean turtle1/pose?"
    }
    assert typo_notes(empty, [Series("turtle2/pos", "x")], "turtle2") == {
        "turtle2/pos": "nothing publishes turtle2/pos: did you mean turtle2/pose?"
    }
