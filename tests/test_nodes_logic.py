"""Pure logic of the nodes: battery, status, goal checks, timer schedule."""

import math

import pytest

from messages import NavigateToRequest
from nodes.battery import drain, make_status
from nodes.goal import clearance_speed, goal_problem, heading_error_deg
from nodes.runtime import _Timer
from sim.world import Obstacle, World

WORLD = World(size=10.0, obstacles=[Obstacle(x=8.0, y=8.0, radius=0.5)])


def test_battery_drains_with_time_and_distance_and_never_below_zero():
    assert drain(100.0, 10.0, 0.0, 0.1, 1.0) == pytest.approx(99.0)
    assert drain(100.0, 0.0, 3.0, 0.1, 1.0) == pytest.approx(97.0)
    assert drain(0.5, 10.0, 10.0, 0.1, 1.0) == 0.0


def test_status_heading_in_degrees_and_world_velocity():
    s = make_status(1.0, 2.0, -math.pi / 2, 2.0, 50.0)
    assert s.theta == pytest.approx(270.0)
    assert (s.vel_x, s.vel_y) == pytest.approx((0.0, -2.0))
    assert make_status(0, 0, -1e-18, 0, 1).theta == 0.0


@pytest.mark.parametrize(
    "x, y, theta, problem",
    [
        (math.nan, 1.0, 0.0, "x is nan"),
        (1.0, math.inf, 0.0, "y is inf"),
        (1.0, 1.0, -math.inf, "theta is -inf"),
        (11.0, 1.0, 0.0, "outside the world"),
        (1.0, -0.1, 0.0, "outside the world"),
        (8.1, 8.1, 0.0, "inside an obstacle"),
    ],
)
def test_invalid_goals(x, y, theta, problem):
    assert problem in goal_problem(NavigateToRequest(x=x, y=y, theta=theta), WORLD)


def test_valid_goals():
    assert goal_problem(NavigateToRequest(x=0.0, y=10.0, theta=720.0), WORLD) is None


def test_heading_error():
    assert heading_error_deg(math.radians(179), math.radians(-179)) == pytest.approx(2.0)


def test_clearance_speed_brakes_to_the_safety_distance():
    assert clearance_speed(1.4, 0.4, 2.0) == pytest.approx(2.0)
    assert clearance_speed(0.4, 0.4, 2.0) == 0.0
    assert clearance_speed(0.1, 0.4, 2.0) == 0.0


def test_timer_keeps_an_absolute_grid_and_skips_missed_ticks():
    t = _Timer(0.1, lambda: None, start=100.0)
    assert t.deadline == pytest.approx(100.1)
    t.advance(100.1003)  # on time, callback took 0.3 ms
    assert t.deadline == pytest.approx(100.2)
    t.advance(100.4501)  # a 250 ms stall: next tick back on the grid, not bunched
    assert t.deadline == pytest.approx(100.5)
