"""Patrol, unit-tested without Zenoh: ``turtlectl.testing.FakeNode`` runs the class on the real
node runtime with a fake clock; ``answer`` plays the navigator."""

from __future__ import annotations

from patrol import Patrol

from turtlectl.messages import NavigateToRequest, NavigateToResponse
from turtlectl.testing import FakeNode


def reached(goal: NavigateToRequest) -> list:
    return [NavigateToResponse(success=True, time_taken=1.0, x=goal.x, y=goal.y, theta=goal.theta % 360)]


def test_it_drives_round_the_square_one_corner_a_goal():
    goals: list[NavigateToRequest] = []
    with FakeNode(Patrol, {"side": 2.0, "cx": 5.0, "cy": 5.0, "laps": 1}) as fake:
        fake.answer("navigate_to", lambda goal: goals.append(goal) or reached(goal))
        fake.advance(10.0)  # a goal a second while none runs: four corners, then done
        assert [(g.x, g.y, round(g.theta)) for g in goals] == [(4, 4, 0), (6, 4, 90), (6, 6, 180), (4, 6, -90)]
        assert fake.instance.done


def test_a_corner_not_reached_is_tried_again():
    answers = iter([[], [NavigateToResponse(success=False, time_taken=1.0, reason="blocked")], None])
    goals: list[NavigateToRequest] = []

    def navigator(goal: NavigateToRequest) -> list:
        goals.append(goal)
        answer = next(answers)
        return reached(goal) if answer is None else answer

    with FakeNode(Patrol, {"side": 2.0, "cx": 5.0, "cy": 5.0}) as fake:
        fake.answer("navigate_to", navigator)
        fake.advance(3.0)
        assert [(g.x, g.y) for g in goals] == [(4, 4)] * 3  # no answer, blocked, then reached
        assert fake.instance.reached == 1
