"""sim.turtles: where a spawned turtle may go, its name, and the others as solid
bodies; with sim.kinematics.collide, a turtle driven into another stops two radii from it."""

from __future__ import annotations

import math

from turtlectl.messages.world import Obstacle, World
from turtlectl.sim.kinematics import TurtleState, collide
from turtlectl.sim.turtles import bodies, free_name, placement_problem, spawn_problem

WORLD = World(size=11.0, obstacles=[Obstacle(x=2.0, y=9.0, radius=0.5)], turtle_radius=0.3)
ONE = {"turtle1": TurtleState(x=5.5, y=5.5, theta=0.0)}


def test_an_unnamed_turtle_gets_the_first_free_turtle_n():
    assert free_name({}) == "turtle1"
    assert free_name({"turtle1": 0, "turtle3": 0}) == "turtle2"
    assert free_name({"turtle1": 0, "turtle2": 0}) == "turtle3"


def test_a_spawn_is_refused_with_its_reason():
    assert spawn_problem(WORLD, ONE, "turtle2", 2.0, 2.0, 0.0) is None
    assert spawn_problem(WORLD, ONE, "turtle1", 2.0, 2.0, 0.0) == "a turtle named turtle1 exists"
    assert "not a turtle name" in str(spawn_problem(WORLD, ONE, "a/b", 2.0, 2.0, 0.0))
    assert "not a turtle name" in str(spawn_problem(WORLD, ONE, "@x", 2.0, 2.0, 0.0))
    assert "at most 63" in str(spawn_problem(WORLD, ONE, "a" * 64, 2.0, 2.0, 0.0))
    assert spawn_problem(WORLD, ONE, "turtlectl", 2.0, 2.0, 0.0) == (
        "'turtlectl' is the first part of the system's own keys (turtlectl/...); choose another name"
    )
    assert spawn_problem(WORLD, ONE, "t", 12.0, 2.0, 0.0) == "(12, 2) is outside the world [0, 11] m"
    assert spawn_problem(WORLD, ONE, "t", 2.0, 9.2, 0.0) == "(2, 9.2) is inside an obstacle"
    assert spawn_problem(WORLD, ONE, "t", 5.9, 5.5, 0.0) == (
        "(5.9, 5.5) is 0.40 m from turtle1, nearer than two turtle radii (0.6 m)"
    )
    assert spawn_problem(WORLD, ONE, "t", 6.1, 5.5, 0.0) is None  # exactly two radii: touching is fine
    assert spawn_problem(WORLD, ONE, "t", math.nan, 5.5, 0.0) == "x is nan"


def test_a_teleport_may_not_land_on_another_turtle_but_on_its_own_place():
    assert placement_problem(WORLD, 5.5, 5.5, 0.0, {}) is None  # turtle1 itself: the others only
    assert placement_problem(WORLD, 5.6, 5.5, 0.0, ONE) is not None


def test_a_turtle_driven_into_another_stops_two_radii_from_it_in_contact():
    other = bodies(WORLD, {**ONE, "turtle2": TurtleState(x=7.0, y=5.5, theta=math.pi)}, but="turtle2")
    assert other == [Obstacle(x=5.5, y=5.5, radius=0.6)]
    before = TurtleState(x=6.2, y=5.5, theta=math.pi, v=1.0)
    after = TurtleState(x=6.0, y=5.5, theta=math.pi, v=1.0)
    stopped, contact = collide(before, after, other)
    assert contact and stopped.v == 0.0 and math.isclose(stopped.x, 6.1)
    away, contact = collide(stopped, TurtleState(x=6.2, y=5.5, theta=0.0), other)
    assert not contact and away.x == 6.2  # away from it is free
