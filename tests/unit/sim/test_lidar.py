"""Scan geometry (numpy ray casting) against hand-computed distances."""

import math

import numpy as np
import pytest

from tests.integration.harness import obstacles_in_view
from turtlectl.messages.world import Obstacle, World
from turtlectl.sim.lidar import beam_angles, cast_rays, new_phantoms

EMPTY = World(size=10.0)


def test_walls_from_the_centre():
    angles = np.array([0.0, math.pi / 2, math.pi, -math.pi / 2, math.pi / 4])
    ranges = cast_rays(5.0, 5.0, 0.0, angles, EMPTY, 100.0)
    assert ranges == pytest.approx([5.0, 5.0, 5.0, 5.0, 5.0 * math.sqrt(2)])


def test_angles_are_relative_to_the_heading():
    ranges = cast_rays(2.0, 5.0, math.pi, np.array([0.0]), EMPTY, 100.0)
    assert ranges[0] == pytest.approx(2.0)


def test_circle_hit_distance():
    world = World(size=10.0, obstacles=[Obstacle(x=8.0, y=5.0, radius=1.0)])
    ranges = cast_rays(5.0, 5.0, 0.0, np.array([0.0, math.pi]), world, 100.0)
    assert ranges == pytest.approx([2.0, 5.0])


def test_tangent_and_miss():
    world = World(size=10.0, obstacles=[Obstacle(x=8.0, y=6.0, radius=1.0)])
    ranges = cast_rays(5.0, 5.0, 0.0, np.array([0.0, math.radians(-10)]), world, 100.0)
    assert ranges[0] == pytest.approx(3.0)  # tangent at (8, 5)
    assert ranges[1] == pytest.approx(5.0 / math.cos(math.radians(10)))  # misses, hits the wall


def test_obstacle_behind_the_turtle_is_not_seen_ahead():
    world = World(size=10.0, obstacles=[Obstacle(x=3.0, y=5.0, radius=0.5)])
    assert cast_rays(5.0, 5.0, 0.0, np.array([0.0]), world, 100.0)[0] == pytest.approx(5.0)


def test_inside_an_obstacle_reads_zero():
    world = World(size=10.0, obstacles=[Obstacle(x=5.0, y=5.0, radius=1.0)])
    assert cast_rays(5.2, 5.0, 0.0, np.array([0.0, 1.0]), world, 100.0) == pytest.approx([0.0, 0.0])


def test_beyond_range_max_is_inf():
    ranges = cast_rays(5.0, 5.0, 0.0, np.array([0.0]), EMPTY, 3.0)
    assert math.isinf(ranges[0])


def test_beam_angles_full_circle_has_no_duplicate():
    angles = beam_angles(-math.pi, math.pi, 4)
    assert angles == pytest.approx([-math.pi, -math.pi / 2, 0.0, math.pi / 2])
    assert beam_angles(-1.0, 1.0, 3) == pytest.approx([-1.0, 0.0, 1.0])


def test_three_obstacles_in_view():
    world = World(
        size=11.0,
        obstacles=[
            Obstacle(x=7.0, y=5.5, radius=0.4),
            Obstacle(x=5.5, y=7.0, radius=0.4),
            Obstacle(x=4.0, y=5.5, radius=0.4),
        ],
    )
    angles = beam_angles(-math.pi, math.pi, 72)
    ranges = cast_rays(5.5, 5.5, 0.0, angles, world, 3.0)
    assert obstacles_in_view(ranges, angles) == 3
    assert obstacles_in_view(np.full(4, np.inf), angles[:4]) == 0


def test_phantoms_appear_at_the_given_distance_and_rate():
    rng = np.random.default_rng(3)
    born = [p for _ in range(1000) for p in new_phantoms(rng, 5.0, 5.0, 2.0, 0.2, 1.5, 0.2)]
    assert 320 < len(born) < 480  # Poisson, mean 400
    assert all(math.hypot(p.x - 5.0, p.y - 5.0) == pytest.approx(1.5) and p.radius == 0.2 for p in born)
    assert new_phantoms(rng, 5.0, 5.0, 0.0, 0.2, 1.5, 0.2) == []
