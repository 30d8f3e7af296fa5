"""The simulator's pure kinematics (turtlesim's rules)."""

import math

import pytest

from turtlectl.messages.world import TURTLESIM_SIZE, Limits, Obstacle
from turtlectl.sim.kinematics import STEP, TurtleState, accelerate, collide, effective_command, step, wrap_angle

LIMITS = Limits(max_linear_speed=4.0, max_angular_speed=9.0, max_linear_accel=10.0, max_angular_accel=40.0)


def test_straight_line_one_second():
    s = TurtleState(x=1.0, y=1.0, theta=0.0)
    for _ in range(int(round(1.0 / STEP))):
        s = step(s, 2.0, 0.0, STEP, TURTLESIM_SIZE)
    assert s.x == pytest.approx(1.0 + 2.0 * 62 * STEP)
    assert s.y == pytest.approx(1.0)
    assert s.v == 2.0


def test_heading_is_integrated_before_position():
    s = step(TurtleState(x=5.0, y=5.0, theta=0.0), 1.0, math.pi / 2 / STEP, STEP, 11.0)
    assert s.theta == pytest.approx(math.pi / 2)
    assert s.x == pytest.approx(5.0)
    assert s.y == pytest.approx(5.0 + STEP)


def test_full_turn_in_place_keeps_position_and_wraps():
    s = TurtleState(x=3.0, y=3.0, theta=0.0)
    for _ in range(100):
        s = step(s, 0.0, 2 * math.pi / (100 * STEP), STEP, 11.0)
    assert (s.x, s.y) == (3.0, 3.0)
    assert -math.pi <= s.theta < math.pi
    assert abs(wrap_angle(s.theta)) < 1e-9


@pytest.mark.parametrize(
    "theta, x, y", [(0.0, 11.0, 5.0), (math.pi / 2, 5.0, 11.0), (-math.pi, 0.0, 5.0), (-math.pi / 2, 5.0, 0.0)]
)
def test_walls_clamp_position(theta, x, y):
    s = TurtleState(x=5.0, y=5.0, theta=theta)
    for _ in range(200):
        s = step(s, 4.0, 0.0, STEP, 11.0)
    assert s.x == pytest.approx(x, abs=1e-9)
    assert s.y == pytest.approx(y, abs=1e-9)


def test_command_times_out_after_one_second():
    assert effective_command(1.0, 0.5, 0.99, LIMITS) == (1.0, 0.5)
    assert effective_command(1.0, 0.5, 1.01, LIMITS) == (0.0, 0.0)
    assert effective_command(1.0, 0.5, None, LIMITS) == (0.0, 0.0)


def test_command_is_clipped_to_limits_both_ways():
    assert effective_command(10.0, -20.0, 0.0, LIMITS) == (4.0, -9.0)
    assert effective_command(-10.0, 20.0, 0.0, LIMITS) == (-4.0, 9.0)


def test_non_finite_command_is_ignored():
    assert effective_command(math.nan, 0.0, 0.0, LIMITS) == (0.0, 0.0)
    assert effective_command(0.0, math.inf, 0.0, LIMITS) == (0.0, 0.0)


@pytest.mark.parametrize(
    "angle, wrapped", [(0.0, 0.0), (math.pi, -math.pi), (3 * math.pi / 2, -math.pi / 2), (-3 * math.pi, -math.pi)]
)
def test_wrap_angle(angle, wrapped):
    assert wrap_angle(angle) == pytest.approx(wrapped)


def test_acceleration_is_limited_both_ways():
    s = TurtleState(x=0, y=0, theta=0, v=1.0, w=-1.0)
    assert accelerate(s, 4.0, 9.0, 0.1, LIMITS) == pytest.approx((2.0, 3.0))
    assert accelerate(s, -4.0, -9.0, 0.1, LIMITS) == pytest.approx((0.0, -5.0))
    assert accelerate(s, 1.05, -1.0, 0.1, LIMITS) == pytest.approx((1.05, -1.0))


def test_reaching_full_speed_takes_speed_over_accel():
    s = TurtleState(x=0, y=5, theta=0)
    steps = 0
    while s.v < 4.0:
        s = step(s, *accelerate(s, 4.0, 0.0, STEP, LIMITS), STEP, 100.0)
        steps += 1
    assert steps * STEP == pytest.approx(0.4, abs=STEP)


def drive_into(obstacles, start, theta, speed, seconds):
    """Poses of a turtle driven at ``speed`` m/s for ``seconds`` s, as the simulator steps it."""
    s = TurtleState(x=start[0], y=start[1], theta=theta)
    poses = []
    for _ in range(int(round(seconds / STEP))):
        s, contact = collide(s, step(s, speed, 0.0, STEP, TURTLESIM_SIZE), obstacles)
        poses.append((s, contact))
    return poses


def test_a_declared_obstacle_is_solid_the_turtle_stops_at_its_surface():
    # the case: {"linear": 1.0} from (2, 7.5) facing the obstacle at (2, 9), r 0.5
    obstacles = [Obstacle(x=2.0, y=9.0, radius=0.5)]
    poses = drive_into(obstacles, (2.0, 7.5), math.pi / 2, 1.0, 3.0)
    assert all(math.hypot(s.x - 2.0, s.y - 9.0) >= 0.5 - 1e-9 for s, _ in poses)
    last, contact = poses[-1]
    assert contact and last.y == pytest.approx(8.5) and last.v == 0.0
    assert not poses[0][1]  # no contact before it gets there


def test_a_turtle_touching_an_obstacle_can_turn_and_leave():
    obstacles = [Obstacle(x=2.0, y=9.0, radius=0.5)]
    touching = TurtleState(x=2.0, y=8.5, theta=math.pi / 2)
    away, contact = collide(touching, step(touching, -1.0, 0.0, STEP, TURTLESIM_SIZE), obstacles)
    assert not contact and away.y < 8.5
    along = TurtleState(x=2.0, y=8.5, theta=0.0)  # tangent: sliding along the surface is free
    moved, contact = collide(along, step(along, 1.0, 0.0, STEP, TURTLESIM_SIZE), obstacles)
    assert not contact and moved.x > 2.0


def test_a_fast_step_cannot_tunnel_through_a_small_obstacle():
    obstacles = [Obstacle(x=5.0, y=5.0, radius=0.01)]
    before = TurtleState(x=4.97, y=5.0, theta=0.0)
    after, contact = collide(before, step(before, 4.0, 0.0, STEP, TURTLESIM_SIZE), obstacles)
    assert contact and after.x == pytest.approx(4.99)
