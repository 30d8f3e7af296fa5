"""nodes.planner: the shortest way around circles, checked against geometry and a grid search."""

import heapq
import math
import random

import numpy as np
import pytest

from turtlectl.messages.world import Obstacle
from turtlectl.nodes.planner import Arc, Circle, Segment, containing, escape, inflate, shortest_path, wall_plugs


def _clear_of(path, circles, size, spacing=0.005):
    points = path.points(spacing)
    assert np.all(points >= -1e-6) and np.all(points <= size + 1e-6), "the path leaves the world"
    for c in circles:
        d = np.hypot(points[:, 0] - c.x, points[:, 1] - c.y)
        assert d.min() >= c.r - 1e-6, f"the path enters {c} by {c.r - d.min():.6f} m"


def _continuous(path):
    for a, b in zip(path.pieces, path.pieces[1:], strict=False):
        assert math.dist(a.point(a.length), b.point(0.0)) < 1e-6
        turn = (b.heading(0.0) - a.heading(a.length) + math.pi) % (2 * math.pi) - math.pi
        assert abs(turn) < 1e-5, f"a corner of {math.degrees(turn):.3f} deg between {a} and {b}"


def _grid_length(start, goal, circles, size, n=160):
    """A conservative 8-connected grid search: cells whose square could touch a circle are
    blocked, so its path is a valid one, never shorter than the true shortest."""
    h = size / n
    centres = (np.arange(n + 1)) * h
    gx, gy = np.meshgrid(centres, centres, indexing="ij")
    free = np.ones_like(gx, dtype=bool)
    for c in circles:
        free &= np.hypot(gx - c.x, gy - c.y) >= c.r + h * math.sqrt(2)
    s = (round(start[0] / h), round(start[1] / h))
    g = (round(goal[0] / h), round(goal[1] / h))
    if not free[s] or not free[g]:
        return None
    best = {s: 0.0}
    heap = [(0.0, s)]
    steps = [(dx, dy, h * math.hypot(dx, dy)) for dx in (-1, 0, 1) for dy in (-1, 0, 1) if dx or dy]
    while heap:
        d, (i, j) = heapq.heappop(heap)
        if (i, j) == g:
            return d + math.dist(start, (s[0] * h, s[1] * h)) + math.dist(goal, (g[0] * h, g[1] * h))
        if d > best[(i, j)]:
            continue
        for dx, dy, w in steps:
            v = (i + dx, j + dy)
            if 0 <= v[0] <= n and 0 <= v[1] <= n and free[v] and d + w < best.get(v, math.inf):
                best[v] = d + w
                heapq.heappush(heap, (d + w, v))
    return math.inf


def test_nothing_in_the_way_is_one_straight_segment():
    path = shortest_path((1.0, 1.0), (9.0, 2.0), [Circle(5.0, 8.0, 1.0)], 10.0)
    assert path.direct and path.length == pytest.approx(math.hypot(8.0, 1.0))


def test_round_one_circle_it_is_tangent_arc_tangent_of_the_exact_length():
    path = shortest_path((2.0, 5.0), (8.0, 5.0), [Circle(5.0, 5.0, 1.0)], 10.0)
    tangent = math.sqrt(3.0**2 - 1.0)  # from 3 m away to a circle of 1 m
    arc = math.pi - 2 * math.acos(1.0 / 3.0)
    assert [type(p) for p in path.pieces] == [Segment, Arc, Segment]
    assert path.length == pytest.approx(2 * tangent + arc, abs=1e-9)
    _continuous(path)


def test_a_gap_between_circles_is_used_while_open_and_gone_around_once_closed():
    circles = [Circle(5.0, 3.4, 1.5), Circle(5.0, 6.6, 1.5)]  # 0.2 m apart
    through = shortest_path((2.0, 5.0), (8.0, 5.0), circles, 10.0)
    assert through is not None and through.direct
    closed = [Circle(5.0, 3.4, 1.7), Circle(5.0, 6.6, 1.7)]  # overlapping
    path = shortest_path((2.0, 5.0), (8.0, 5.0), closed, 10.0)
    assert path is not None and path.length > through.length + 1.0
    _clear_of(path, closed, 10.0)
    _continuous(path)


def test_an_enclosed_goal_has_no_path():
    ring = [Circle(5.0 + 1.5 * math.cos(a), 5.0 + 1.5 * math.sin(a), 0.5) for a in np.linspace(0, 2 * math.pi, 12)]
    assert containing(5.0, 5.0, ring) is None
    assert shortest_path((1.0, 1.0), (5.0, 5.0), ring, 10.0) is None
    assert shortest_path((5.0, 5.0), (1.0, 1.0), ring, 10.0) is None


def test_a_wall_to_wall_barrier_has_no_path_and_a_goal_inside_a_circle_neither():
    barrier = [Circle(5.0, y, 0.8) for y in np.arange(0.0, 10.5, 1.0)]
    assert shortest_path((1.0, 5.0), (9.0, 5.0), barrier, 10.0) is None
    assert shortest_path((1.0, 5.0), (5.1, 5.0), [Circle(5.0, 5.0, 1.0)], 10.0) is None


def test_a_circle_over_the_wall_is_gone_round_on_the_open_side():
    circles = [Circle(5.0, 1.0, 2.0)]  # crosses the bottom wall
    path = shortest_path((1.0, 1.0), (9.0, 1.0), circles, 10.0)
    assert path is not None
    _clear_of(path, circles, 10.0)
    assert max(y for _, y in path.outline()) > 2.9  # over the top


def test_a_gap_between_a_circle_and_a_wall_narrower_than_the_turtle_is_plugged():
    near = Circle(5.0, 9.0, 0.8)  # 0.2 m below the top wall of a 10 m world
    plugs = wall_plugs([near, Circle(5.0, 5.0, 1.0)], 10.0, 0.3)
    assert len(plugs) == 1  # the other is 4 m from every wall: no plug
    assert (plugs[0].x, plugs[0].y, plugs[0].r) == pytest.approx((5.0, 10.0, 0.2 + 0.02))
    assert shortest_path((1.0, 9.8), (9.0, 9.8), [near], 10.0) is not None  # through the 0.2 m gap
    path = shortest_path((1.0, 9.8), (9.0, 9.8), [near, *plugs], 10.0)
    assert path is not None
    _clear_of(path, [near, *plugs], 10.0)
    assert min(y for _, y in path.outline()) < 8.3  # round its underside (it reaches down to 8.2)
    assert (
        wall_plugs([near], 10.0, 0.15) == [] and wall_plugs([Circle(5.0, 9.5, 0.8)], 10.0, 0.3) == []
    )  # wide, or closed


def test_a_start_within_a_margin_escapes_it():
    circles = [Circle(5.0, 5.0, 1.0)]
    assert shortest_path((5.5, 5.0), (9.0, 5.0), circles, 10.0) is None
    shrunk = escape(5.5, 5.0, circles)
    assert shrunk[0].r == pytest.approx(0.5)
    path = shortest_path((5.5, 5.0), (9.0, 5.0), shrunk, 10.0)
    assert path is not None and path.direct


def test_inflate_grows_each_obstacle():
    assert inflate([Obstacle(x=1.0, y=2.0, radius=0.5)], 0.4) == [Circle(1.0, 2.0, 0.9)]


def _random_case(rng, most=9):
    size = rng.uniform(6.0, 14.0)
    circles = [
        Circle(rng.uniform(0, size), rng.uniform(0, size), rng.uniform(0.2, size / 6))
        for _ in range(rng.randint(1, most))
    ]
    while True:
        start, goal = (rng.uniform(0, size), rng.uniform(0, size)), (rng.uniform(0, size), rng.uniform(0, size))
        if containing(*start, circles) is None and containing(*goal, circles) is None:
            return size, circles, start, goal


@pytest.mark.parametrize("seed", range(300))
def test_a_planned_path_keeps_out_of_every_circle_and_inside_the_world(seed):
    size, circles, start, goal = _random_case(random.Random(seed))
    path = shortest_path(start, goal, circles, size)
    if path is None:
        return
    assert math.dist(path.start, start) < 1e-9 and math.dist(path.end, goal) < 1e-9
    _clear_of(path, circles, size)
    _continuous(path)


@pytest.mark.parametrize("seed", range(40))
def test_a_planned_path_is_no_longer_than_a_fine_grid_search_and_exists_when_the_grid_finds_one(seed):
    size, circles, start, goal = _random_case(random.Random(1000 + seed), most=14)
    path = shortest_path(start, goal, circles, size)
    grid = _grid_length(start, goal, circles, size)
    if grid is None:  # start or goal in a cell the grid blocks: nothing to compare
        return
    if math.isinf(grid):
        return  # the (conservative) grid found no way: the planner may or may not
    assert path is not None, "the grid found a way the planner did not"
    assert path.length <= grid + 1e-9, (path.length, grid)
    assert path.length >= 0.92 * grid - 4 * size / 160  # an 8-connected grid is within 8 % (and its snapping)
