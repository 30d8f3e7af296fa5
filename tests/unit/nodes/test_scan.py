"""Scan geometry (numpy ray casting) against hand-computed distances."""

import math

import numpy as np
import pytest

from messages.world import Obstacle, World
from nodes.scan import circles_corridor_clearance, corridor_clearance, hit_points, off_walls
from sim.lidar import beam_angles, cast_rays

EMPTY = World(size=10.0)


def test_hit_points_and_walls():
    angles = np.array([0.0, math.pi / 2, math.pi])
    ranges = cast_rays(2.0, 0.3, 0.0, angles, EMPTY, 1.0)  # only the wall behind... is 2 m: inf
    points = hit_points(2.0, 0.3, 0.0, np.array([1.0, 9.7, math.inf]), angles)
    assert points == pytest.approx(np.array([[3.0, 0.3], [2.0, 10.0]]))
    assert off_walls(points, 10.0) == pytest.approx(np.array([[3.0, 0.3]]))
    assert math.isinf(ranges[0]) and math.isinf(ranges[2])


def test_corridor_ignores_what_is_beside_the_path():
    points = np.array([[4.0, 5.5], [6.0, 5.1], [3.0, 5.0]])  # 0.5 m aside, 0.1 m aside, behind
    assert corridor_clearance(points, 5.0, 5.0, 0.0, 0.3) == pytest.approx(1.0)
    assert corridor_clearance(points, 5.0, 5.0, math.pi, 0.3) == pytest.approx(2.0)
    assert corridor_clearance(points, 5.0, 5.0, math.pi / 2, 0.3) == math.inf
    assert corridor_clearance(np.zeros((0, 2)), 5.0, 5.0, 0.0, 0.3) == math.inf


def test_a_wall_never_blocks_a_goal_next_to_it():
    # driving along a wall towards a goal on it: the scan sees the wall, the corridor ignores it
    angles = beam_angles(-math.pi, math.pi, 360)
    ranges = cast_rays(2.0, 0.2, 0.3, angles, EMPTY, 10.0)
    points = off_walls(hit_points(2.0, 0.2, 0.3, ranges, angles), EMPTY.size)
    assert points.shape == (0, 2)
    world = World(size=10.0, obstacles=[Obstacle(x=4.0, y=0.9, radius=0.2)])
    ranges = cast_rays(2.0, 0.2, 0.3, angles, world, 10.0)
    points = off_walls(hit_points(2.0, 0.2, 0.3, ranges, angles), world.size)
    assert 1.6 < corridor_clearance(points, 2.0, 0.2, math.atan2(0.7, 2.0), 0.3) < 2.0


def test_the_corridor_meets_declared_circles_exactly():
    obstacles = [Obstacle(x=5.0, y=1.0, radius=0.5)]  # centre 1 m beside the line y = 0
    # corridor half-width 0.3: the circle reaches 0.5 m across, into the strip [-0.3, 0.3]? no
    assert circles_corridor_clearance(obstacles, 0.0, 0.0, 0.0, 0.3) == (math.inf, None)
    # half-width 0.6: it meets the strip where it is 0.6 m across: x = 5 - sqrt(0.25 - 0.16) = 4.7
    nearest, which = circles_corridor_clearance(obstacles, 0.0, 0.0, 0.0, 0.6)
    assert nearest == pytest.approx(5.0 - math.sqrt(0.25 - 0.16)) and which is obstacles[0]
    # straight ahead and behind
    ahead = [Obstacle(x=3.0, y=0.0, radius=0.5), Obstacle(x=-2.0, y=0.0, radius=0.5)]
    assert circles_corridor_clearance(ahead, 0.0, 0.0, 0.0, 0.3)[0] == pytest.approx(2.5)
    assert circles_corridor_clearance(ahead, 0.0, 0.0, math.pi, 0.3)[0] == pytest.approx(1.5)
    # a circle the turtle touches, ahead of it: nothing to drive
    assert circles_corridor_clearance([Obstacle(x=0.5, y=0.0, radius=0.5)], 0.0, 0.0, 0.0, 0.3)[0] == 0.0


def test_declared_circles_and_their_scan_agree():
    world = World(size=20.0, obstacles=[Obstacle(x=6.0, y=5.3, radius=0.7)])
    angles = beam_angles(-math.pi, math.pi, 3600)
    points = hit_points(2.0, 5.0, 0.0, cast_rays(2.0, 5.0, 0.0, angles, world, 15.0), angles)
    points = off_walls(points, world.size)
    from_scan = corridor_clearance(points, 2.0, 5.0, 0.0, 0.3)
    declared, _ = circles_corridor_clearance(world.obstacles, 2.0, 5.0, 0.0, 0.3)
    assert from_scan == pytest.approx(declared, abs=0.01)
