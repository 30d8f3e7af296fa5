"""nodes.goal: goals refused before anything moves, and the speed allowed near obstacles."""

import math

import pytest

from turtlectl.messages import NavigateToRequest
from turtlectl.messages.angles import heading_difference_degrees
from turtlectl.messages.world import Obstacle, World
from turtlectl.nodes.goal import allowed_speed, clearance_speed, goal_problem

WORLD = World(size=10.0, obstacles=[Obstacle(x=8.0, y=8.0, radius=0.5)])


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
    assert heading_difference_degrees(math.radians(179), math.radians(-179)) == pytest.approx(2.0)


def test_clearance_speed_brakes_to_the_safety_distance():
    assert clearance_speed(1.4, 0.4, 2.0) == pytest.approx(2.0)
    assert clearance_speed(0.4, 0.4, 2.0) == 0.0
    assert clearance_speed(0.1, 0.4, 2.0) == 0.0


DEFAULT_WORLD = World(
    obstacles=[
        Obstacle(x=2.0, y=9.0, radius=0.5),
        Obstacle(x=9.0, y=9.0, radius=0.6),
        Obstacle(x=9.0, y=2.0, radius=0.4),
    ]
)


SPAWN = (5.544445, 5.544445)


@pytest.mark.parametrize("goal", [(2.0, 9.6), (2.6, 9.0), (9.0, 2.8)])
def test_a_goal_nearer_an_obstacle_than_the_turtle_keeps_is_refused_with_the_distance(goal):
    problem = goal_problem(NavigateToRequest(x=goal[0], y=goal[1], theta=0.0), DEFAULT_WORLD, 0.45)
    assert (
        problem is not None
        and problem.startswith(f"({goal[0]:g}, {goal[1]:g}) is ")
        and "m from the obstacle at (" in problem
    )
    assert "keeps 0.45 m" in problem


@pytest.mark.parametrize("goal", [(2.0, 10.0), (10.5, 10.5), (9.93, 9.90), (9.0, 2.86)])
def test_a_goal_behind_an_obstacle_but_clear_of_it_is_a_goal(goal):
    assert goal_problem(NavigateToRequest(x=goal[0], y=goal[1], theta=0.0), DEFAULT_WORLD, 0.45) is None


def test_allowed_speed_ignores_what_lies_beyond_the_goal_and_stops_within_the_safety_distance():
    assert allowed_speed(2.0, 1.0, 0.4, 2.0) == math.inf
    assert allowed_speed(0.4, 3.0, 0.4, 2.0) == 0.0
    assert allowed_speed(1.4, 3.0, 0.4, 2.0) == pytest.approx(2.0)
