"""The control law against the pure kinematics with the robot's limits:
exact arrival, quickly, from anywhere, without overshoot or oscillation."""

import math
import random

import pytest

from turtlectl.messages.world import TURTLESIM_SIZE, Limits
from turtlectl.nodes.control import (
    Gains,
    Phase,
    Pose2D,
    Tolerances,
    choose_direction,
    control_step,
    remaining_time,
    resting_pose,
    rotate_drive_rotate_time,
    trapezoid_time,
)
from turtlectl.sim.kinematics import STEP, TurtleState, accelerate, effective_command, step, wrap_angle

LIMITS = Limits()
GAINS = Gains()
POS_TOL = 0.01
HEAD_TOL = math.radians(0.5)
TOLERANCES = Tolerances(position=POS_TOL, heading=HEAD_TOL)


def step_law(pose, goal, phase, direction):
    return control_step(pose, goal, phase=phase, direction=direction, limits=LIMITS, gains=GAINS, tolerances=TOLERANCES)


def drive(start: TurtleState, goal: tuple[float, float, float], max_time: float = 10.0):
    """Closed loop as in the system: a command per 16 ms step from the latest pose,
    followed by the simulator within its speed and acceleration limits."""
    s, phase, t = start, Phase.POSITION, 0.0
    target = Pose2D(*goal)
    direction = choose_direction(s, target, LIMITS)
    trace = []
    while t < max_time:
        cmd = step_law(s, target, phase, direction)
        phase, direction = cmd.phase, cmd.direction  # as the driver keeps them
        if phase is Phase.DONE:
            return s, t, trace
        v, w = effective_command(cmd.linear, cmd.angular, 0.0, LIMITS)
        s = step(s, *accelerate(s, v, w, STEP, LIMITS), STEP, TURTLESIM_SIZE)
        trace.append(s)
        t += STEP
    raise AssertionError(f"goal {goal} not reached from {start} within {max_time} s; ended at {s}")


def errors(s: TurtleState, goal):
    return math.hypot(goal[0] - s.x, goal[1] - s.y), abs(math.remainder(goal[2] - s.theta, 2 * math.pi))


def test_random_goals_within_three_metres_are_reached_exactly_within_two_seconds():
    rng = random.Random(7)
    worst = 0.0
    for _ in range(200):
        start = TurtleState(x=5.5, y=5.5, theta=rng.uniform(-math.pi, math.pi))
        bearing, dist = rng.uniform(-math.pi, math.pi), rng.uniform(0.0, 3.0)
        goal = (5.5 + dist * math.cos(bearing), 5.5 + dist * math.sin(bearing), rng.uniform(-math.pi, math.pi))
        end, t, _ = drive(start, goal)
        pos_err, head_err = errors(end, goal)
        assert pos_err <= POS_TOL and head_err <= HEAD_TOL
        worst = max(worst, t)
    assert worst < 1.8  # leaves room for the system's latency under the capstone's 2 s


def test_goals_across_the_world_beat_rotate_drive_rotate():
    rng = random.Random(11)
    ratios = []
    for _ in range(100):
        sx, sy, st = rng.uniform(0, TURTLESIM_SIZE), rng.uniform(0, TURTLESIM_SIZE), rng.uniform(-math.pi, math.pi)
        goal = (rng.uniform(0, TURTLESIM_SIZE), rng.uniform(0, TURTLESIM_SIZE), rng.uniform(-math.pi, math.pi))
        end, t, _ = drive(TurtleState(x=sx, y=sy, theta=st), goal)
        pos_err, head_err = errors(end, goal)
        assert pos_err <= POS_TOL and head_err <= HEAD_TOL
        ratios.append(t / rotate_drive_rotate_time(Pose2D(sx, sy, st), Pose2D(*goal), LIMITS))
    assert sum(ratios) / len(ratios) <= 0.85


@pytest.mark.parametrize(
    "start, goal",
    [
        ((5.5, 5.5, 0.0), (5.5, 5.5, 0.0)),  # already there
        ((5.5, 5.5, 0.0), (5.5, 5.5, math.pi - 0.01)),  # heading only
        ((5.5, 5.5, 0.0), (5.5, 5.5, -math.pi / 2)),  # heading only, the other way
        ((5.5, 5.5, 0.0), (2.5, 5.5, 0.0)),  # straight behind
        ((5.5, 5.5, 0.0), (2.5, 5.5, math.pi)),  # behind, facing it at the end
        ((5.5, 5.5, 0.0), (0.0, 0.0, 0.0)),  # corner
        ((5.5, 5.5, 0.0), (TURTLESIM_SIZE, 3.0, math.pi / 2)),  # on the wall
        ((0.2, 0.2, math.pi), (0.0, 0.0, 0.0)),  # from a corner, into it
        ((1.0, 10.0, -2.0), (10.0, 1.0, 2.0)),  # across the world
        ((5.5, 5.5, 0.0), (5.5, 5.503, 0.0)),  # inside the tolerance sideways
        ((5.5, 5.5, 0.0), (5.5, 5.52, 0.0)),  # just outside it sideways
    ],
)
def test_edge_goals(start, goal):
    end, _, _ = drive(TurtleState(x=start[0], y=start[1], theta=start[2]), goal)
    pos_err, head_err = errors(end, goal)
    assert pos_err <= POS_TOL
    assert head_err <= HEAD_TOL


@pytest.mark.parametrize("seed", range(20))
def test_no_overshoot_and_no_oscillation_at_the_goal(seed):
    rng = random.Random(seed)
    start = TurtleState(x=rng.uniform(2, 9), y=rng.uniform(2, 9), theta=rng.uniform(-3, 3))
    goal = (rng.uniform(2, 9), rng.uniform(2, 9), rng.uniform(-3, 3))
    _, _, trace = drive(start, goal)
    # once within the tolerance of the position, the turtle stays within it
    inside = [i for i, s in enumerate(trace) if math.hypot(goal[0] - s.x, goal[1] - s.y) <= POS_TOL]
    assert inside and all(math.hypot(goal[0] - s.x, goal[1] - s.y) <= POS_TOL for s in trace[inside[0] :])
    # the final turn in place does not swing back and forth: the turn rate changes
    # sign at most once (the steering left over from driving, then the final turn)
    spins = [s.w for s in trace[inside[0] :] if abs(s.w) > 1e-9]
    assert sum(1 for a, b in zip(spins, spins[1:], strict=False) if (a > 0) != (b > 0)) <= 1


def test_commands_stay_within_limits():
    for seed in range(10):
        rng = random.Random(seed)
        s = TurtleState(x=rng.uniform(0, 11), y=rng.uniform(0, 11), theta=rng.uniform(-3, 3))
        goal = (rng.uniform(0, 11), rng.uniform(0, 11), rng.uniform(-3, 3))
        cmd = step_law(s, Pose2D(*goal), Phase.POSITION, 1)
        assert abs(cmd.linear) <= LIMITS.max_linear_speed and abs(cmd.angular) <= LIMITS.max_angular_speed


def test_goal_behind_is_driven_in_reverse():
    here = Pose2D(5.0, 5.0, 0.0)
    assert choose_direction(here, Pose2D(3.0, 5.0, 0.0), LIMITS) == -1
    assert choose_direction(here, Pose2D(3.0, 5.0, math.pi), LIMITS) == 1  # unless it must face it
    cmd = step_law(here, Pose2D(3.0, 5.0, 0.0), Phase.POSITION, -1)
    assert cmd.linear < 0 and cmd.angular == pytest.approx(0.0, abs=1e-9)


def test_trapezoid_and_triangle_times():
    assert trapezoid_time(4.0, 4.0, 10.0) == pytest.approx(4.0 / 4.0 + 4.0 / 10.0)
    assert trapezoid_time(0.4, 4.0, 10.0) == pytest.approx(2 * math.sqrt(0.04))
    assert trapezoid_time(-0.4, 4.0, 10.0) == trapezoid_time(0.4, 4.0, 10.0)
    assert rotate_drive_rotate_time(Pose2D(0, 0, 0), Pose2D(4, 0, 0), LIMITS) == pytest.approx(trapezoid_time(4, 4, 10))


def test_remaining_time_is_zero_at_the_goal():
    assert remaining_time(Pose2D(1, 1, 0.3), Pose2D(1, 1, 0.3), 1, LIMITS) == 0.0
    assert remaining_time(Pose2D(1, 1, 0.0), Pose2D(5, 1, 0.0), 1, LIMITS) == pytest.approx(trapezoid_time(4, 4, 10))


@pytest.mark.parametrize("lag", [0, 1])
@pytest.mark.parametrize(("v", "w"), [(0.0, 6.0), (0.0, -1.5), (0.0, 0.2), (0.3, 0.0), (-2.0, 3.0), (4.0, -6.2)])
def test_resting_pose_is_where_the_simulator_brakes_to_after_lag_steps_of_the_old_command(v, w, lag):
    s = TurtleState(x=5.0, y=5.0, theta=3.0, v=v, w=w)
    rest = resting_pose(s, v, w, LIMITS, lag=lag)
    for _ in range(lag):  # the stop is still on its way
        s = step(s, *accelerate(s, v, w, STEP, LIMITS), STEP, 100.0)
    while s.v != 0.0 or s.w != 0.0:
        s = step(s, *accelerate(s, 0.0, 0.0, STEP, LIMITS), STEP, 100.0)
    assert abs(wrap_angle(rest.theta - s.theta)) <= 1e-9
    # the position follows the heading as it turns; the prediction keeps the present heading
    assert math.hypot(rest.x - s.x, rest.y - s.y) <= (1e-9 if w == 0.0 else 0.1 * abs(v))


def drive_late(start: TurtleState, goal: tuple[float, float, float], late_at: int, late: int) -> float:
    """``drive``'s loop, but the law misses ``late`` steps from step ``late_at`` on (a busy
    machine: the simulator keeps the last command): the time (s) to arrive."""
    s, phase, t, k = start, Phase.POSITION, 0.0, 0
    target = Pose2D(*goal)
    direction = choose_direction(s, target, LIMITS)
    cmd = None
    while t < 10.0:
        if cmd is None or not late_at <= k < late_at + late:
            cmd = step_law(s, target, phase, direction)
            phase, direction = cmd.phase, cmd.direction
            if phase is Phase.DONE:
                return t
        v, w = effective_command(cmd.linear, cmd.angular, 0.0, LIMITS)
        s = step(s, *accelerate(s, v, w, STEP, LIMITS), STEP, TURTLESIM_SIZE)
        t, k = t + STEP, k + 1
    raise AssertionError(f"goal {goal} not reached from {start} within 10 s; ended at {s}")


@pytest.mark.parametrize("late", [1, 2, 3])
def test_steps_missed_while_braking_cost_a_fraction_of_a_second(late):
    """Criterion 1's goal from the spawn (3 m, heading reversed) on a busy machine: steps missed
    while braking, an overshoot, then a half turn to drive the goal's first direction again
    would take 2.83 s, not 1.76 s.  Kept as the driver keeps it, the direction taken
    close in holds: the overshoot is backed out of."""
    start, goal = TurtleState(x=5.544445, y=5.544445, theta=0.0), (8.5, 5.5, math.pi)
    on_time = drive_late(start, goal, 0, 0)
    worst = max(drive_late(start, goal, at, late) for at in range(50, 80))
    assert worst <= on_time + 0.4, f"{worst:.3f} s with {late} missed step(s), {on_time:.3f} s on time"
