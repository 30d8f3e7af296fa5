"""Navigation among turtles (nodes.traffic), pure, on a fake clock: who gives way,
where a turtle with the right of way is about to be, scan hits on a turtle not remembered as
obstacles, and two navigators (goal machines) on the simulator's kinematics driving across
each other's way: both arrive, and their centres never come within two turtle radii."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.unit.nodes.test_goal_machine import scan  # a full-circle scan, taken where it says
from turtlectl.messages import GoalState, LaserScan, NavigateToRequest, Pose, Turtles, Twist
from turtlectl.messages.world import Limits, Obstacle, World
from turtlectl.nodes.goal_machine import GoalMachine, Reply
from turtlectl.nodes.params import NavigatorParams
from turtlectl.nodes.traffic import HORIZON, STALE, Traffic, gives_way
from turtlectl.sim.kinematics import STEP, TurtleState, accelerate, effective_command, step
from turtlectl.sim.lidar import beam_angles, cast_rays

WORLD = World(size=11.0)
LIMITS = Limits()


def turtles(stamp_s: float, **where: tuple[float, float]) -> Turtles:
    return Turtles(
        names=list(where),
        x=[p[0] for p in where.values()],
        y=[p[1] for p in where.values()],
        theta=[0.0] * len(where),
        stamp=int(stamp_s * 1e9),
    )


def test_the_order_of_giving_way_is_the_same_in_every_navigator():
    assert gives_way("turtle2", "turtle1") and not gives_way("turtle1", "turtle2")
    assert gives_way("turtle3", "turtle2") != gives_way("turtle2", "turtle3")


def test_a_moving_turtle_with_the_right_of_way_is_seen_where_it_is_about_to_be():
    t = Traffic("turtle2", radius=0.3)
    t.update(turtles(0.0, turtle1=(2.0, 5.0), turtle2=(5.0, 2.0)), now=0.0)
    t.update(turtles(0.1, turtle1=(2.2, 5.0), turtle2=(5.0, 2.0)), now=0.1)  # turtle1: 2 m/s along x
    points = t.points(now=0.1)
    xs = points[:, 0]
    assert xs.min() == pytest.approx(2.2 - 0.3) and xs.max() == pytest.approx(2.2 + 2.0 * HORIZON + 0.3)
    assert np.allclose(points[:, 1].mean(), 5.0)
    # turtle1 gives way to nobody: it sees turtle2's body only
    t1 = Traffic("turtle1", radius=0.3)
    t1.update(turtles(0.0, turtle1=(2.0, 5.0), turtle2=(5.0, 2.0)), now=0.0)
    t1.update(turtles(0.1, turtle1=(2.0, 5.0), turtle2=(5.0, 2.2)), now=0.1)
    assert np.hypot(*(t1.points(0.1) - [5.0, 2.2]).T).max() == pytest.approx(0.3)


def test_a_standing_turtle_is_a_body_only_and_stale_news_is_nothing():
    t = Traffic("turtle2", radius=0.3)
    t.update(turtles(0.0, turtle1=(2.0, 5.0)), now=0.0)
    t.update(turtles(0.1, turtle1=(2.0, 5.0)), now=0.1)
    assert len(t.points(0.1)) == 12 and t.centres(0.1) == [(2.0, 5.0, 0.0)]
    assert len(t.points(0.1 + STALE + 0.01)) == 0 and t.centres(0.1 + STALE + 0.01) == []


def test_scan_hits_on_another_turtle_are_not_remembered_as_obstacles():
    """A moving turtle's trail, kept in the costmap, walled two turtles in (seen live: both
    'blocked' after 10 s, each waiting for the other's remembered trail to clear)."""
    m = GoalMachine(NavigatorParams(), WORLD, LIMITS, "turtle2")
    here = Pose(x=2.0, y=5.0, theta=0.0)
    m.pose(here, 0.0)
    m.turtles(turtles(0.0, turtle1=(4.0, 5.0), turtle2=(2.0, 5.0)), 0.0)
    angles = beam_angles(-math.pi, math.pi, 72)
    seen = World(size=WORLD.size, obstacles=[Obstacle(x=4.0, y=5.0, radius=0.3)])
    ranges = cast_rays(here.x, here.y, here.theta, angles, seen, 10.0)
    scan = LaserScan(
        angle_min=float(angles[0]),
        angle_max=float(angles[-1]),
        angle_increment=float(angles[1] - angles[0]),
        range_min=0.0,
        range_max=10.0,
        ranges=ranges.tolist(),
        origin_x=here.x,
        origin_y=here.y,
        origin_theta=here.theta,
    )
    m.scan(scan, 0.0)
    assert len(m.surroundings.scan_points) > 0  # the scan saw turtle1
    assert len(m.unknown_points) == 0 and m.surroundings.unknown == []  # and nothing is remembered
    # standing, it is planned round where it is now
    assert [(c.x, c.y) for c in m.surroundings.seen(0.0)] == [(4.0, 5.0)]


def drive_two(starts, goals, max_time=20.0):
    """Two navigators on the kinematics, each pose a control step, each command a step late,
    ``turtles`` every 4th step (as the simulator publishes it): each one's outcome, the least
    distance between their centres, and the states the giver of way went through."""
    names = list(starts)
    machines = {n: GoalMachine(NavigatorParams(), WORLD, LIMITS, n) for n in names}
    states = {n: TurtleState(x=x, y=y, theta=th) for n, (x, y, th) in starts.items()}
    pending = {n: [Twist()] for n in names}
    outcome: dict[str, Reply] = {}
    went_through: set[GoalState] = set()
    now, least = 0.0, math.inf
    for n in names:
        machines[n].pose(Pose(x=states[n].x, y=states[n].y, theta=states[n].theta), now)
        x, y, theta = goals[n]
        machines[n].start(NavigateToRequest(x=x, y=y, theta=theta), n, now)
    ticks = 0
    while now < max_time and len(outcome) < len(names):
        if ticks % 4 == 0:
            msg = turtles(now, **{n: (s.x, s.y) for n, s in states.items()})
            for m in machines.values():
                m.turtles(msg, now)
        if ticks % 12 == 0:  # a scan every 12 steps (5 Hz), of nothing but the other turtle: seen through traffic
            for n, m in machines.items():
                s = states[n]
                m.scan(scan(blocking=False, at=Pose(x=s.x, y=s.y, theta=s.theta)), now)
        for n in names:
            s, m = states[n], machines[n]
            actions = m.pose(Pose(x=s.x, y=s.y, theta=s.theta, linear_velocity=s.v, angular_velocity=s.w), now)
            for a in actions:
                if isinstance(a, Reply) and a.response is not None and hasattr(a.response, "success"):
                    outcome.setdefault(n, a)
            if m.goal is not None:
                went_through.add(m.goal.driver.state)
            twist = [a for a in actions if isinstance(a, Twist)]
            pending[n].append(twist[-1] if twist else pending[n][-1])
            cmd = pending[n].pop(0)
            v, w = effective_command(cmd.linear, cmd.angular, 0.0, LIMITS)
            states[n] = step(s, *accelerate(s, v, w, STEP, LIMITS), STEP, WORLD.size)
        a, b = (states[n] for n in names)
        least = min(least, math.hypot(a.x - b.x, a.y - b.y))
        now += STEP
        ticks += 1
    return outcome, least, went_through


@pytest.mark.parametrize(
    ("starts", "goals"),
    [
        # across each other's way, reaching the crossing at the same moment
        (
            {"turtle1": (2.0, 5.5, 0.0), "turtle2": (5.5, 2.0, math.pi / 2)},
            {"turtle1": (9.0, 5.5, 0.0), "turtle2": (5.5, 9.0, 90.0)},
        ),
        (
            {"turtle2": (2.0, 5.5, 0.0), "turtle3": (5.5, 9.0, -math.pi / 2)},
            {"turtle2": (9.0, 5.5, 0.0), "turtle3": (5.5, 2.0, -90.0)},
        ),
    ],
)
def test_two_turtles_sent_across_each_others_way_both_arrive_and_never_touch(starts, goals):
    outcome, least, _ = drive_two(starts, goals)
    assert set(outcome) == set(starts), outcome
    assert all(r.response.success for r in outcome.values()), {n: r.response for n, r in outcome.items()}
    assert least >= 2 * WORLD.turtle_radius, least


def test_two_turtles_swapping_places_head_on_both_arrive_without_touching():
    """Each goal is where the other starts: the one giving way waits while the other comes, the
    other goes round it standing (planned again with a scan), then it goes."""
    starts = {"turtle2": (3.0, 5.5, 0.0), "turtle3": (8.0, 5.5, math.pi)}
    goals = {"turtle2": (8.0, 5.5, 0.0), "turtle3": (3.0, 5.5, 180.0)}
    outcome, least, _ = drive_two(starts, goals, max_time=25.0)
    assert all(r.response.success for r in outcome.values()) and len(outcome) == 2, outcome
    assert least >= 2 * WORLD.turtle_radius, least


def test_without_the_others_poses_the_same_crossing_collides():
    """What the traffic prevents: with no ``turtles`` (the scan alone is not in this loop
    either), the two centres pass within two radii of each other."""
    starts = {"turtle1": (2.0, 5.5, 0.0), "turtle2": (5.5, 2.0, math.pi / 2)}
    goals = {"turtle1": (9.0, 5.5, 0.0), "turtle2": (5.5, 9.0, 90.0)}
    original = GoalMachine.turtles
    try:
        GoalMachine.turtles = lambda self, msg, now: None  # type: ignore[method-assign]
        _, least, _ = drive_two(starts, goals)
    finally:
        GoalMachine.turtles = original  # type: ignore[method-assign]
    assert least < 2 * WORLD.turtle_radius
