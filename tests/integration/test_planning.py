"""Planning against the real processes: goals behind obstacles are reached round them, goals
walled in by declared obstacles or too near one are refused at once, what
only the scan sees is planned round as it comes into view, and a goal walled in by it ends
"blocked" after blocked_timeout.

Undeclared obstacles are the obstacle detector's ``undeclared_obstacles``: the scan sees
them, the navigator is not told (the simulator does not collide with them either, so the
poses show exactly how close the turtle came).
"""

from __future__ import annotations

import math
import queue

import pytest

from tests.integration.harness import running_system
from turtlectl.messages import GoalState, Pose, decode
from turtlectl.messages.keys import POSE

pytestmark = pytest.mark.integration

ROBOT_RADIUS = 0.3  # the navigator's default

WORLD = """
[world]
obstacles = [
  { x = 2.0, y = 9.0, radius = 0.5 },
  { x = 9.0, y = 9.0, radius = 0.6 },
  { x = 9.0, y = 2.0, radius = 0.4 },
  { x = 10.5000, y = 5.0000, radius = 0.4 },  # a ring round (9.5, 5)
  { x = 10.2071, y = 5.7071, radius = 0.4 },
  { x = 9.5000, y = 6.0000, radius = 0.4 },
  { x = 8.7929, y = 5.7071, radius = 0.4 },
  { x = 8.5000, y = 5.0000, radius = 0.4 },
  { x = 8.7929, y = 4.2929, radius = 0.4 },
  { x = 9.5000, y = 4.0000, radius = 0.4 },
  { x = 10.2071, y = 4.2929, radius = 0.4 },
]
[[node]]
name = "sim"
run = "sim"
[[node]]
name = "navigator"
run = "navigator"
[node.params]
blocked_timeout = 2.0
[[node]]
name = "status_monitor"
run = "status_monitor"
[[node]]
name = "obstacle_detector"
run = "obstacle_detector"
[node.params]
range_max = 2.0             # it sees 2 m: what lies farther comes into view on the way
undeclared_obstacles = [
  { x = 5.5, y = 3.0, radius = 0.4 },   # on the way from (2.5, 3) to (8.5, 3)
  { x = 5.5, y = 7.0, radius = 0.3 },   # sitting on the goal (5.5, 7)
]
"""


@pytest.fixture(scope="module")
def system(tmp_path_factory):
    path = tmp_path_factory.mktemp("planning") / "planning.toml"
    path.write_text(WORLD)
    with running_system(path) as system:
        yield system


class Track:
    """Every pose while it is open."""

    def __init__(self, system):
        self.poses: queue.SimpleQueue[Pose] = queue.SimpleQueue()
        self.sub = system.session.declare_subscriber(POSE, lambda s: self.poses.put(decode(s.payload.to_bytes(), Pose)))

    def close(self) -> list[Pose]:
        self.sub.undeclare()
        out = []
        while not self.poses.empty():
            out.append(self.poses.get())
        return out


def nearest(poses: list[Pose], x: float, y: float, radius: float) -> float:
    """How close (m) the turtle's centre came to the surface of the circle at (x, y)."""
    return min(math.hypot(p.x - x, p.y - y) for p in poses) - radius


def test_a_goal_straight_behind_a_declared_obstacle_is_reached_round_it_without_touching_it(system):
    system.teleport(9.0, 7.0, math.pi / 2)  # the obstacle at (9, 9), r 0.6, straight ahead
    track = Track(system)
    response, _, feedback = system.navigate(9.0, 10.5, 90.0)
    poses = track.close()
    assert response.success, response
    assert response.position_error <= 0.01 and response.heading_error <= 0.5
    assert len(feedback[0].path) > 2 and feedback[0].path[0] == pytest.approx((9.0, 7.0), abs=1e-3)
    assert max(abs(x - 9.0) for x, _ in feedback[0].path) > 0.6 + ROBOT_RADIUS  # round it
    assert nearest(poses, 9.0, 9.0, 0.6) >= ROBOT_RADIUS, "the turtle came nearer the obstacle than its size"


def test_something_undeclared_that_comes_into_view_on_the_path_is_planned_round(system):
    system.teleport(2.5, 3.0, 0.0)  # the undeclared (5.5, 3), r 0.4, is 2.6 m ahead: out of the scan's range
    track = Track(system)
    response, _, feedback = system.navigate(8.5, 3.0, 0.0)
    poses = track.close()
    assert response.success, response
    assert len(feedback[0].path) == 2  # nothing known in the way at first: straight
    assert feedback[-1].replans >= 1, feedback[-1]
    assert any(len(f.path) > 2 for f in feedback)  # a way round it (past it, the last may be straight again)
    assert nearest(poses, 5.5, 3.0, 0.4) >= ROBOT_RADIUS


def test_a_goal_walled_in_by_what_only_the_scan_sees_ends_blocked_after_blocked_timeout(system):
    system.teleport(5.5, 5.5, math.pi / 2)  # the goal (5.5, 7) lies in the undeclared (5.5, 7), r 0.3
    track = Track(system)
    response, _, feedback = system.navigate(5.5, 7.0, 90.0)
    poses = track.close()
    assert not response.success and not response.refused and response.reason == "blocked", response
    assert "something the scan sees lay within 0.45 m of the goal" in response.detail, response.detail
    assert "blocked_timeout of 2 s" in response.detail
    assert 2.0 <= response.time_taken < 3.0, response.time_taken
    assert GoalState.REPLANNING in {f.state for f in feedback} and feedback[-1].path == []
    assert nearest(poses, 5.5, 7.0, 0.3) >= ROBOT_RADIUS


def test_a_goal_too_near_a_declared_obstacle_is_refused_at_once_with_the_distance(system):
    system.teleport(5.0, 5.0, 0.0)
    response, elapsed, _ = system.navigate(2.0, 9.7, 0.0)  # 0.2 m from the obstacle at (2, 9), r 0.5
    assert response.refused and elapsed < 1.0, response
    assert response.reason == "invalid goal", response
    assert response.detail.startswith("(2, 9.7) is 0.20 m from the obstacle at (2, 9)"), response


def test_a_goal_walled_in_by_declared_obstacles_is_refused_at_once(system):
    system.teleport(5.0, 5.0, 0.0)
    response, elapsed, _ = system.navigate(9.5, 5.0, 0.0)  # inside the ring of eight round (9.5, 5)
    assert response.refused and elapsed < 1.0, response
    assert response.reason == "unreachable", response
    assert response.detail.startswith("no way from (5.00, 5.00) to (9.5, 5)"), response
