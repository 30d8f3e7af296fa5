"""nodes.battery: drain, travel and the status built from a pose."""

import math

import pytest

from messages import Pose
from nodes.battery import drain, make_status, travelled


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
