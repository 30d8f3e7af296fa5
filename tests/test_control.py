"""The control law against the pure kinematics: exact arrival, quickly, from anywhere."""

import math
import random

import pytest

from nodes.control import Gains, Phase, control_step
from sim.kinematics import STEP, TurtleState, effective_command, step
from sim.world import TURTLESIM_SIZE, Limits

LIMITS = Limits()
GAINS = Gains()
POS_TOL = 0.01
HEAD_TOL = math.radians(1.0)


def drive(start: TurtleState, goal: tuple[float, float, float], max_time: float = 10.0):
    """Closed loop as in the system: a command per 16 ms step computed from the latest pose."""
    s, phase, t = start, Phase.DRIVE, 0.0
    speeds = []
    while t < max_time:
        cmd = control_step(s.x, s.y, s.theta, *goal, phase, LIMITS, GAINS, POS_TOL, HEAD_TOL)
        phase = cmd.phase
        if phase is Phase.DONE:
            return s, t, speeds
        v, w = effective_command(cmd.linear, cmd.angular, 0.0, LIMITS)
        speeds.append((v, w))
        s = step(s, v, w, STEP, TURTLESIM_SIZE)
        t += STEP
    raise AssertionError(f"goal {goal} not reached from {start} within {max_time} s; ended at {s}")


def errors(s: TurtleState, goal):
    return math.hypot(goal[0] - s.x, goal[1] - s.y), abs(math.remainder(goal[2] - s.theta, 2 * math.pi))


def test_random_goals_within_three_metres_are_reached_exactly_within_two_seconds():
    rng = random.Random(7)
    worst = 0.0
    for _ in range(300):
        start = TurtleState(x=5.5, y=5.5, theta=rng.uniform(-math.pi, math.pi))
        bearing, dist = rng.uniform(-math.pi, math.pi), rng.uniform(0.0, 3.0)
        goal = (5.5 + dist * math.cos(bearing), 5.5 + dist * math.sin(bearing), rng.uniform(-math.pi, math.pi))
        end, t, _ = drive(start, goal)
        pos_err, head_err = errors(end, goal)
        assert pos_err <= POS_TOL and head_err <= HEAD_TOL
        worst = max(worst, t)
    assert worst < 2.0


@pytest.mark.parametrize(
    "start, goal",
    [
        ((5.5, 5.5, 0.0), (5.5, 5.5, 0.0)),  # already there
        ((5.5, 5.5, 0.0), (5.5, 5.5, math.pi - 0.01)),  # heading only
        ((5.5, 5.5, 0.0), (2.5, 5.5, 0.0)),  # straight behind
        ((5.5, 5.5, 0.0), (0.0, 0.0, 0.0)),  # corner
        ((5.5, 5.5, 0.0), (TURTLESIM_SIZE, 3.0, math.pi / 2)),  # on the wall
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


def test_commands_stay_within_limits_and_do_not_oscillate_at_the_goal():
    _, _, speeds = drive(TurtleState(x=2.0, y=2.0, theta=1.0), (5.0, 4.0, -1.0))
    assert all(abs(v) <= LIMITS.max_linear_speed and abs(w) <= LIMITS.max_angular_speed for v, w in speeds)
    # the final in-place turn never reverses direction
    final_turn = [w for v, w in speeds[-20:] if v == 0.0 and w != 0.0]
    assert all(w > 0 for w in final_turn) or all(w < 0 for w in final_turn)


def test_goal_behind_is_driven_in_reverse():
    cmd = control_step(5.0, 5.0, 0.0, 3.0, 5.0, 0.0, Phase.DRIVE, LIMITS, GAINS, POS_TOL, HEAD_TOL)
    assert cmd.reverse and cmd.linear < 0 and cmd.angular == pytest.approx(0.0, abs=1e-9)
