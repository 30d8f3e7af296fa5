"""nodes.battery: drain, travel and the status built from a pose."""

import math

import pytest

from turtlectl.messages import Pose
from turtlectl.nodes.battery import drain, make_status, travelled


def test_battery_drains_with_time_and_distance_and_never_below_zero():
    assert drain(100.0, 10.0, 0.0, 0.1, 1.0) == pytest.approx(99.0)
    assert drain(100.0, 0.0, 3.0, 0.1, 1.0) == pytest.approx(97.0)
    assert drain(0.5, 10.0, 10.0, 0.1, 1.0) == 0.0


def test_status_heading_in_degrees_and_world_velocity():
    s = make_status(1.0, 2.0, -math.pi / 2, 2.0, 50.0)
    assert s.theta == pytest.approx(270.0)
    assert (s.vel_x, s.vel_y) == pytest.approx((0.0, -2.0))
    assert make_status(0, 0, -1e-18, 0, 1).theta == 0.0


def test_teleports_and_resets_are_not_travel():
    before = Pose(x=1.0, y=1.0, theta=0.0, stamp=1_000_000_000)
    driven = Pose(x=1.06, y=1.0, theta=0.0, stamp=1_016_000_000)  # 0.06 m in 16 ms: 3.75 m/s
    jumped = Pose(x=7.4, y=1.0, theta=0.0, stamp=1_016_000_000)  # 6.4 m in 16 ms
    assert travelled(before, driven, 4.0) == pytest.approx(0.06)
    assert travelled(before, jumped, 4.0) == 0.0
    # a lost pose in between: twice the time, twice the distance, still travel
    assert travelled(before, Pose(x=1.12, y=1.0, theta=0.0, stamp=1_032_000_000), 4.0) == pytest.approx(0.12)


def test_poses_read_at_10_hz_still_measure_travel():
    """The status monitor reads the newest pose at its 10 Hz tick: 0.1 s apart."""
    before = Pose(x=1.0, y=1.0, theta=0.0, stamp=1_000_000_000)
    driven = Pose(x=1.4, y=1.0, theta=0.0, stamp=1_096_000_000)  # six poses later: 0.4 m in 96 ms
    jumped = Pose(x=3.0, y=1.0, theta=0.0, stamp=1_096_000_000)  # 2 m in 96 ms: no drive does that
    assert travelled(before, driven, 4.0) == pytest.approx(0.4)
    assert travelled(before, jumped, 4.0) == 0.0
    # an arc at 4 m/s turning at 2 pi rad/s for 0.1 s: the chord is within 1.7 % of the arc
    radius, angle = 4.0 / (2 * math.pi), 2 * math.pi * 0.1
    arc_end = Pose(
        x=1.0 + radius * math.sin(angle), y=1.0 + radius * (1 - math.cos(angle)), theta=angle, stamp=1_100_000_000
    )
    assert travelled(before, arc_end, 4.0) == pytest.approx(0.4, rel=0.017)
