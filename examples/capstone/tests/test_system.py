"""The capstone in the real system, through turtlectl's pytest plugin: the ``turtlectl_system``
fixture launches ``launch.toml`` (pytest.ini) on a free port, once for this module, waits until
every node is ready and hands each test a ``turtlectl.Client``."""

from __future__ import annotations

import threading

import pytest

import turtlectl
from turtlectl.messages import NavigateToFeedback, NavigateToRequest


def test_every_node_runs_and_the_status_is_ours(turtlectl_system):
    client = turtlectl_system
    assert {n.name for n in client.nodes()} >= {"sim", "navigator", "status_monitor", "obstacle_detector"}
    status = client.latest("robot/status", timeout=5.0)
    assert type(status).__name__ == "TurtleStatus" and 0.0 <= status.battery <= 100.0
    assert client.param("navigator", "goal_timeout") == 30.0


def test_a_goal_is_reached_with_feedback(turtlectl_system):
    client = turtlectl_system
    feedback: list[NavigateToFeedback] = []
    response = client.goto(8.5, 5.5, 180.0, on_feedback=feedback.append, timeout=10.0)
    assert response.success, response
    assert abs(response.x - 8.5) < 0.2 and abs(response.y - 5.5) < 0.2
    assert feedback, "no feedback while it drove"


def test_a_newer_goal_preempts_and_a_cancel_stops(turtlectl_system):
    client = turtlectl_system
    first_fed = threading.Event()
    first = client.send_goal("navigate_to", NavigateToRequest(x=2.0, y=2.0, theta=0.0), lambda fb: first_fed.set())
    assert first_fed.wait(5.0), "no feedback for the first goal"
    second_fed = threading.Event()
    second = client.send_goal("navigate_to", NavigateToRequest(x=9.0, y=2.0, theta=0.0), lambda fb: second_fed.set())
    assert first.result(5.0).reason == "preempted"
    assert second_fed.wait(5.0), "no feedback for the second goal"
    assert client.cancel().ok
    with pytest.raises(turtlectl.GoalCanceled) as canceled:  # a goal canceled raises, as a future's would
        second.result(5.0)
    assert canceled.value.response.reason == "canceled"
