"""cli.tools.format: how messages, goals and plans are shown (headings in [0, 360), lines that fit)."""

import json
import math

import pytest

from tests.unit.messages.samples import FEEDBACK
from turtlectl.cli.tools.format import (
    csv_header,
    csv_row,
    heading_text,
    message_block,
    message_json,
    outcome_line,
    progress_line,
    select_field,
    teleport_line,
)
from turtlectl.messages import (
    LaserScan,
    NavigateToFeedback,
    NavigateToResponse,
    Pose,
    TurtleStatus,
    Twist,
)
from turtlectl.runtime.client.errors import BadInput


def test_formats():
    scan = LaserScan(
        angle_min=0, angle_max=1, angle_increment=0.1, range_min=0, range_max=5, ranges=[1.0] * 20 + [math.inf]
    )
    block = message_block(scan)
    assert block.startswith("# turtlectl/LaserScan\n") and "... (21 values)]" in block and block.endswith("---")
    assert "inf" in message_block(scan, full=True)
    status = TurtleStatus(x=1.0, y=2.0, theta=3.0, vel_x=-0.0, vel_y=0.0, battery=50.0, stamp=7, seq=1)
    assert select_field(scan, "ranges.20") == math.inf and select_field(status, "battery") == 50
    with pytest.raises(BadInput, match="no field 'nope'"):
        select_field(status, "nope")
    assert csv_header(status) == "x,y,theta,vel_x,vel_y,battery,stamp,seq"
    assert csv_row(status).startswith("1.0,2.0,3.0,")


@pytest.mark.parametrize(
    "degrees, shown", [(359.97, "0.0"), (360.0, "0.0"), (-0.0, "0.0"), (-45, "315.0"), (720.25, "0.2")]
)
def test_headings_are_shown_in_0_360_after_rounding(degrees, shown):
    assert heading_text(degrees) == shown


def test_goal_outcome_never_says_360_degrees():
    done = NavigateToResponse(success=True, time_taken=1.0, x=0.5, y=0.5, theta=359.99)
    assert "0.0 deg" in outcome_line(done) and "360" not in outcome_line(done)


def test_teleport_speaks_the_degrees_it_was_given():
    assert teleport_line(2, 2, 45) == "teleported to (2, 2, 45 deg)"
    assert teleport_line(4, 6, -90) == "teleported to (4, 6, 270 deg)"


@pytest.mark.parametrize("columns", [200, 80, 60, 40, 20, 5])
def test_the_progress_line_never_wraps(columns):
    line = progress_line(FEEDBACK, columns)
    assert len(line) <= columns - 1 or columns == 1
    assert line.startswith("driving"[: columns - 1]) and "\n" not in line and "360" not in line


def test_the_progress_line_keeps_what_fits_and_drops_the_least_useful_first():
    assert "14.5 s" in progress_line(FEEDBACK, 200) and "at (11.08, 11.08, 0 deg)" in progress_line(FEEDBACK, 200)
    narrow = progress_line(FEEDBACK, 50)
    assert "10.123 m" in narrow and "eta" in narrow and "14.5 s" not in narrow
    stale = NavigateToFeedback(**{**{f: getattr(FEEDBACK, f) for f in FEEDBACK.__struct_fields__}, "scan_stale": True})
    assert "no scan" in progress_line(stale, 120)


def test_wildcard_json_names_the_key():
    line = json.loads(message_json(Twist(linear=1.0), "turtle1/cmd_vel"))
    assert line["type"] == "turtlectl/Twist" and line["key"] == "turtle1/cmd_vel" and line["linear"] == 1.0
    assert "key" not in json.loads(message_json(Twist()))
    scan = LaserScan(angle_min=0, angle_max=0, angle_increment=0, range_min=0, range_max=1, ranges=[math.inf])
    assert json.loads(message_json(scan, "obstacles"))["ranges"] == ["Infinity"]  # as in recordings (one rule)


def test_the_outcome_says_why_and_what_to_do_next():
    low = NavigateToResponse(
        success=False,
        time_taken=0.0,
        reason="battery low",
        refused=True,
        detail="battery at 3.0 %, below the navigator's min_battery 5 %: `turtlectl reset` recharges it",
    )
    assert outcome_line(low) == f"refused: battery low ({low.detail})"
    blocked = NavigateToResponse(
        success=False, time_taken=12.0, reason="blocked", detail="the obstacle at (9, 9) stayed within 0.4 m"
    )
    assert outcome_line(blocked).startswith("not reached: blocked after 12.000 s (the obstacle at (9, 9) stayed")


def test_a_block_never_rounds_a_heading_up_to_360_and_writes_booleans_as_json_does():
    status = TurtleStatus(x=1.0, y=2.0, theta=359.99999, vel_x=0.0, vel_y=0.0, battery=50.0)
    assert "theta: 359.99999" in message_block(status)
    assert "contact: true" in message_block(Pose(x=2.0, y=8.5, theta=0.0, contact=True))


def test_non_finite_floats_are_spelled_in_json_as_in_recordings_and_on_the_foxglove_server():
    # one rule wherever turtlectl writes JSON: "Infinity", "-Infinity", "NaN" (messages.jsonform)
    from turtlectl.cli.tools import format as fmt
    from turtlectl.messages import LaserScan
    from turtlectl.messages.jsonform import to_json as recorded

    scan = LaserScan(
        angle_min=0.0,
        angle_max=1.0,
        angle_increment=0.5,
        range_min=0.0,
        range_max=5.0,
        ranges=[1.0, math.inf, -math.inf],
    )
    assert fmt.message_json(scan) == recorded(scan).decode()
    for line in (fmt.message_json(scan), fmt.message_json(scan, key="lab1/obstacles")):
        data = json.loads(line)
        assert data["ranges"] == [1.0, "Infinity", "-Infinity"] and data["origin_x"] == "NaN", line
    assert fmt.fields_line({"ranges": scan.ranges}, json=True) == '[1.0,"Infinity","-Infinity"]'
    assert fmt.fields_line({"origin_x": scan.origin_x}, json=True) == '"NaN"'
    assert '"[1.0,""Infinity"",""-Infinity""]"' in fmt.csv_row(scan)
