"""Scan geometry (numpy ray casting) against hand-computed distances."""

import math

import numpy as np
import pytest

from turtlectl.messages.world import Obstacle, World
from turtlectl.nodes.scan import hit_points, off_walls, path_clearance
from turtlectl.sim.lidar import beam_angles, cast_rays

EMPTY = World(size=10.0)


def test_hit_points_and_walls():
    angles = np.array([0.0, math.pi / 2, math.pi])
    ranges = cast_rays(2.0, 0.3, 0.0, angles, EMPTY, 1.0)  # only the wall behind... is 2 m: inf
    points = hit_points(2.0, 0.3, 0.0, np.array([1.0, 9.7, math.inf]), angles)
    assert points == pytest.approx(np.array([[3.0, 0.3], [2.0, 10.0]]))
    assert off_walls(points, 10.0) == pytest.approx(np.array([[3.0, 0.3]]))
    assert math.isinf(ranges[0]) and math.isinf(ranges[2])


def _straight(x0, y0, x1, y1, spacing=0.01):
    n = max(2, math.ceil(math.hypot(x1 - x0, y1 - y0) / spacing) + 1)
    t = np.linspace(0.0, 1.0, n)
    return np.column_stack((x0 + t * (x1 - x0), y0 + t * (y1 - y0))), t * math.hypot(x1 - x0, y1 - y0)


def test_path_clearance_ignores_what_is_beside_the_path():
    points = np.array([[4.0, 5.5], [6.0, 5.1], [3.0, 5.0]])  # 0.5 m aside, 0.1 m aside, behind
    path, along = _straight(5.0, 5.0, 9.0, 5.0)
    nearest, which = path_clearance(path, along, points, [], 5.0, 5.0, 0.3)
    assert nearest == pytest.approx(1.0 - math.sqrt(0.3**2 - 0.1**2), abs=0.011) and which is None
    path, along = _straight(5.0, 5.0, 5.0, 9.0)
    assert path_clearance(path, along, points, [], 5.0, 5.0, 0.3) == (math.inf, None)
    assert path_clearance(path, along, np.zeros((0, 2)), [], 5.0, 5.0, 0.3) == (math.inf, None)


def test_path_clearance_follows_a_curved_path():
    angles = np.linspace(0.0, math.pi / 2, 200)  # a quarter circle of 2 m round (0, 0), from (2, 0) to (0, 2)
    path = np.column_stack((2.0 * np.cos(angles), 2.0 * np.sin(angles)))
    along = 2.0 * angles
    on_it = np.array([[2.0 * math.cos(1.0), 2.0 * math.sin(1.0)]])  # 2 m along
    assert path_clearance(path, along, on_it, [], 2.0, 0.0, 0.3)[0] == pytest.approx(2.0 - 0.3, abs=0.02)
    straight_ahead = np.array([[2.0, 1.5]])  # ahead of the turtle's heading, but the path bends away
    assert path_clearance(path, along, straight_ahead, [], 2.0, 0.0, 0.3)[0] == math.inf


def test_a_wall_never_blocks_a_goal_next_to_it():
    # driving along a wall towards a goal on it: the scan sees the wall, the path check ignores it
    angles = beam_angles(-math.pi, math.pi, 360)
    ranges = cast_rays(2.0, 0.2, 0.3, angles, EMPTY, 10.0)
    points = off_walls(hit_points(2.0, 0.2, 0.3, ranges, angles), EMPTY.size)
    assert points.shape == (0, 2)


def test_the_path_meets_declared_circles_exactly():
    obstacles = [Obstacle(x=5.0, y=1.0, radius=0.5)]  # centre 1 m beside the line y = 0
    path, along = _straight(0.0, 0.0, 9.0, 0.0, spacing=0.001)
    assert path_clearance(path, along, np.zeros((0, 2)), obstacles, 0.0, 0.0, 0.3) == (math.inf, None)
    # half-width 0.6: it comes within 0.6 m of the surface where it is 1.1 m from the centre: x = 5 - sqrt(1.21 - 1)
    nearest, which = path_clearance(path, along, np.zeros((0, 2)), obstacles, 0.0, 0.0, 0.6)
    assert nearest == pytest.approx(5.0 - math.sqrt(1.21 - 1.0), abs=0.002) and which is obstacles[0]


def test_a_turtle_already_near_something_may_leave_but_not_come_nearer():
    obstacles = [Obstacle(x=0.4, y=0.0, radius=0.2)]  # its surface 0.2 m from the turtle at (0, 0)
    away, along = _straight(0.0, 0.0, -3.0, 0.0)
    assert path_clearance(away, along, np.zeros((0, 2)), obstacles, 0.0, 0.0, 0.3) == (math.inf, None)
    towards, along = _straight(0.0, 0.0, 3.0, 0.0)
    assert path_clearance(towards, along, np.zeros((0, 2)), obstacles, 0.0, 0.0, 0.3)[0] < 0.07
    hit = np.array([[0.2, 0.0]])  # a scan hit 0.2 m ahead: the same
    away_along = _straight(0.0, 0.0, -3.0, 0.0)[1]
    assert path_clearance(away, away_along, hit, [], 0.0, 0.0, 0.3)[0] == math.inf
    assert path_clearance(towards, along, hit, [], 0.0, 0.0, 0.3)[0] < 0.07


def test_declared_circles_and_their_scan_agree():
    world = World(size=20.0, obstacles=[Obstacle(x=6.0, y=5.3, radius=0.7)])
    angles = beam_angles(-math.pi, math.pi, 3600)
    points = hit_points(2.0, 5.0, 0.0, cast_rays(2.0, 5.0, 0.0, angles, world, 15.0), angles)
    points = off_walls(points, world.size)
    path, along = _straight(2.0, 5.0, 12.0, 5.0)
    from_scan, _ = path_clearance(path, along, points, [], 2.0, 5.0, 0.3)
    declared, _ = path_clearance(path, along, np.zeros((0, 2)), world.obstacles, 2.0, 5.0, 0.3)
    assert from_scan == pytest.approx(declared, abs=0.02)
