"""The navigator, unit-tested without Zenoh: its control law as a plain function, and the class on
``FakeNode`` (a fake clock; ``send_goal`` plays the caller, ``deliver`` the simulator)."""

from __future__ import annotations

import math

from navigator import Navigator, NavigatorParams, command

from turtlectl.messages import NavigateToRequest, NavigateToResponse, Pose, Twist
from turtlectl.testing import FakeNode, unstamped

GOAL = NavigateToRequest(x=8.0, y=5.0, theta=90.0)


def test_it_drives_at_a_goal_ahead_and_turns_to_one_behind():
    ahead = command(Pose(x=5.0, y=5.0, theta=0.0), GOAL, NavigatorParams())
    assert ahead is not None and ahead.linear > 0 and abs(ahead.angular) < 1e-9
    behind = command(Pose(x=5.0, y=5.0, theta=math.pi), GOAL, NavigatorParams())
    assert behind is not None and behind.linear < 1e-3 and abs(behind.angular) > 1.0


def test_there_means_at_the_position_and_facing_the_heading():
    assert command(Pose(x=8.0, y=5.0, theta=math.pi / 2), GOAL, NavigatorParams()) is None
    turning = command(Pose(x=8.0, y=5.0, theta=0.0), GOAL, NavigatorParams())
    assert turning is not None and turning.linear == 0.0 and turning.angular > 0


def test_a_goal_gets_feedback_then_its_result_once_there():
    with FakeNode(Navigator) as fake:
        fake.deliver("turtle1/pose", Pose(x=5.0, y=5.0, theta=0.0))
        goal = fake.send_goal("navigate_to", GOAL)
        fake.advance(0.25)  # feedback at 10 Hz while it runs
        assert goal.feedback and goal.feedback[-1].distance_remaining == 3.0
        assert goal.result is None
        fake.deliver("turtle1/pose", Pose(x=8.0, y=5.0, theta=math.pi / 2))
        assert isinstance(goal.result, NavigateToResponse) and goal.result.success
        assert unstamped(fake.published("turtle1/cmd_vel")[-1]) == Twist(linear=0.0, angular=0.0)  # stopped there


def test_a_canceled_goal_stops_the_turtle_and_says_why():
    with FakeNode(Navigator) as fake:
        fake.deliver("turtle1/pose", Pose(x=5.0, y=5.0, theta=0.0))
        goal = fake.send_goal("navigate_to", GOAL)
        fake.advance(0.1)
        assert fake.published("turtle1/cmd_vel")[-1].linear > 0  # driving
        assert goal.cancel().ok
        assert goal.result.reason == "canceled" and not goal.result.success
        assert unstamped(fake.published("turtle1/cmd_vel")[-1]) == Twist(linear=0.0, angular=0.0)


def test_a_newer_goal_preempts_the_running_one():
    with FakeNode(Navigator) as fake:
        fake.deliver("turtle1/pose", Pose(x=5.0, y=5.0, theta=0.0))
        first = fake.send_goal("navigate_to", GOAL)
        second = fake.send_goal("navigate_to", NavigateToRequest(x=2.0, y=2.0, theta=0.0), client="other")
        assert first.result.reason == "preempted"
        assert second.result is None  # running


def test_a_goal_not_there_in_time_ends_timeout():
    with FakeNode(Navigator, {"goal_timeout": 2.0}) as fake:
        fake.deliver("turtle1/pose", Pose(x=5.0, y=5.0, theta=0.0))
        goal = fake.send_goal("navigate_to", GOAL)
        fake.advance(2.5)  # no pose comes: the turtle never gets there
        assert goal.result.reason == "timeout"
