"""Before the simulator moves a turtle (a teleport, a reset) it tells whatever drives it on
``<turtle>/moving`` and waits for the answers; the navigator ends its running goal with the
reason.  The simulator knows nothing of goals: the navigator ends its own."""

from __future__ import annotations

from turtlectl.messages import Ack, Moving, NavigateToRequest, Pose, Reset, TeleportAbsolute
from turtlectl.messages.keys import MOVING, POSE, RESET, TELEPORT, moving_key
from turtlectl.nodes.navigator import Navigator
from turtlectl.runtime.fake import FakeNode
from turtlectl.sim.kinematics import STEP
from turtlectl.sim.node import Simulator


def test_a_teleport_tells_the_turtles_driver_then_moves_it_and_answers_after_its_next_pose():
    with FakeNode(Simulator, name="sim") as fake:
        told: list[tuple[object, int]] = []
        fake.answer(MOVING, lambda request: told.append((request, len(fake.published(POSE)))) or [Ack()])
        replies = fake.request(TELEPORT, TeleportAbsolute(x=3.0, y=3.0, theta=0.0))
        assert told == [(Moving(reason="teleported"), 0)] and replies == []  # not moved yet: no pose since
        fake.advance(STEP + 1e-9)
        pose = fake.published(POSE)[-1]
        assert (pose.x, pose.y) == (3.0, 3.0) and [r.ok for r in replies] == [True], replies


def test_a_reset_tells_every_turtles_driver():
    with FakeNode(Simulator, name="sim") as fake:
        told: list[object] = []
        fake.answer(moving_key("**"), lambda request: told.append(request) or [Ack()])
        fake.request(RESET, Reset())
        assert told == [Moving(reason="reset")]


def test_the_navigator_ends_its_running_goal_with_the_simulators_reason():
    with FakeNode(Navigator) as fake:
        fake.deliver(POSE, Pose(x=2.0, y=5.0, theta=0.0))
        goal = fake.send_goal("navigate_to", NavigateToRequest(x=8.0, y=5.0, theta=0.0))
        assert goal.result is None
        assert fake.request(MOVING, Moving(reason="teleported")) == [Ack(detail="ended the running goal")]
        assert goal.result.reason == "teleported" and not goal.result.success
        assert fake.request(MOVING, Moving(reason="reset")) == [Ack(detail="no goal is running")]
