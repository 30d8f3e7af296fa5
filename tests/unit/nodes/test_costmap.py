"""nodes.costmap: hits remembered where they were seen, cleared by beams that pass through."""

import math

import numpy as np
import pytest

from turtlectl.messages.world import Obstacle, World
from turtlectl.nodes.costmap import PAD, Costmap
from turtlectl.nodes.planner import containing
from turtlectl.nodes.scan import hit_points, off_walls
from turtlectl.sim.lidar import beam_angles, cast_rays

SIZE = 11.0
ANGLES = beam_angles(-math.pi, math.pi, 72)


def look(costmap: Costmap, x: float, y: float, world: World, theta: float = 0.0) -> None:
    """A 72-beam full-turn scan of ``world`` (nothing in it declared) taken at (x, y, theta)."""
    ranges = cast_rays(x, y, theta, ANGLES, world, 10.0)
    hits = off_walls(hit_points(x, y, theta, ranges, ANGLES), world.size)
    costmap.update(x, y, theta, ranges, float(ANGLES[0]), float(ANGLES[1] - ANGLES[0]), 10.0, hits)


def test_a_hit_marks_its_cell_and_a_beam_through_it_later_clears_it():
    costmap = Costmap(SIZE)
    phantom = World(size=SIZE, obstacles=[Obstacle(x=7.0, y=5.0, radius=0.2)])
    look(costmap, 5.0, 5.0, phantom)
    marked = costmap.occupied()
    assert len(marked) and np.all(np.abs(marked[:, 0] - 6.85) < 0.1)  # its near side, 1.8 m east
    look(costmap, 5.0, 5.0, World(size=SIZE))  # gone: the beams go through where it was
    assert len(costmap.occupied()) == 0


def test_the_far_side_of_a_thing_stays_known_after_the_turtle_has_driven_round_it():
    rock = World(size=SIZE, obstacles=[Obstacle(x=5.5, y=5.5, radius=0.5)])
    costmap = Costmap(SIZE)
    look(costmap, 3.0, 5.5, rock)  # from the west
    look(costmap, 8.0, 5.5, rock)  # from the east
    look(costmap, 3.0, 5.5, rock)  # from the west again: its beams stop at the west side
    marked = costmap.occupied()
    assert marked[:, 0].min() < 5.1 and marked[:, 0].max() > 5.9
    circles = costmap.circles()
    assert np.allclose(np.hypot(marked[:, 0] - 5.5, marked[:, 1] - 5.5), 0.5, atol=1e-6)  # where seen, not cells
    for hx, hy in marked:  # every hit lies inside a circle, PAD from its edge
        assert any(math.hypot(hx - c.x, hy - c.y) + PAD <= c.r + 1e-9 for c in circles)


def test_the_nearest_thing_seen_is_measured_to_its_hit_not_its_cell():
    costmap = Costmap(SIZE)
    look(costmap, 5.5, 5.0, World(size=SIZE, obstacles=[Obstacle(x=5.5, y=8.0, radius=0.4)]))
    distance, where = costmap.nearest(5.5, 7.1)
    assert distance == pytest.approx(0.5, abs=1e-6) and where == pytest.approx((5.5, 7.6), abs=1e-6)
    assert Costmap(SIZE).nearest(1.0, 1.0) == (math.inf, None)


def test_only_the_beams_field_of_view_is_cleared():
    costmap = Costmap(SIZE)
    look(costmap, 5.0, 5.0, World(size=SIZE, obstacles=[Obstacle(x=5.0, y=7.0, radius=0.3)]))  # north of it
    before = costmap.occupied()
    ahead = np.array([-0.3, 0.0, 0.3])  # three beams looking east only: nothing there
    costmap.update(5.0, 5.0, 0.0, np.full(3, math.inf), -0.3, 0.3, 10.0, np.zeros((0, 2)))
    assert np.array_equal(costmap.occupied(), before) and len(before)
    costmap.update(5.0, 5.0, math.pi / 2, np.full(3, math.inf), float(ahead[0]), 0.3, 10.0, np.zeros((0, 2)))
    assert len(costmap.occupied()) == 0  # turned north: now they see through it


def test_a_ring_keeps_its_hollow_and_the_circles_stay_few():
    ring = [Obstacle(x=5.5 + 1.5 * math.cos(a), y=5.5 + 1.5 * math.sin(a), radius=0.4) for a in np.linspace(0, 6.2, 12)]
    world = World(size=SIZE, obstacles=ring)
    costmap = Costmap(SIZE)
    for a in np.linspace(0.0, 2 * math.pi, 16, endpoint=False):  # drive round it
        look(costmap, 5.5 + 3.0 * math.cos(a), 5.5 + 3.0 * math.sin(a), world)
    circles = costmap.circles()
    assert 0 < len(circles) <= 24
    assert containing(5.5, 5.5, circles) is None
    assert len(costmap.circles(most=6)) <= 6


def test_nonsense_in_a_scan_changes_nothing_and_raises_nothing():
    costmap = Costmap(SIZE)
    look(costmap, 5.0, 5.0, World(size=SIZE, obstacles=[Obstacle(x=7.0, y=5.0, radius=0.2)]))
    before = costmap.occupied()
    with np.errstate(all="raise"):
        costmap.update(5.0, 5.0, 0.0, np.full(72, math.inf), math.nan, math.nan, 10.0, np.zeros((0, 2)))
    assert np.array_equal(costmap.occupied(), before)


def test_many_things_seen_apart_still_give_at_most_the_circles_asked_for():
    costmap = Costmap(SIZE)
    specks = [(1.05 + 1.5 * i, 1.05 + 1.5 * j) for i in range(6) for j in range(6)]  # 36 cells that touch nothing
    costmap.update(0.0, 0.0, 0.0, np.zeros(0), 0.0, 0.0, 10.0, np.array(specks))
    for most in (24, 6, 1):
        circles = costmap.circles(most=most)
        assert 0 < len(circles) <= most
        assert all(containing(x, y, circles) is not None for x, y in specks)
