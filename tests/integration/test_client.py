"""``turtlectl.Client`` against the real system: the live graph, topics
(latest, subscribe by iteration and by callback, publish), a goal with its feedback,
cancel, parameters (read, set, refused), and errors that carry the command line's exit codes."""

from __future__ import annotations

import threading

import pytest

import turtlectl
from tests.integration.harness import NODES, free_port, running_system
from turtlectl.messages import NavigateToFeedback, Pose, TurtleStatus, Twist

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def system():
    with running_system() as system:
        yield system


def test_the_live_graph(system):
    with turtlectl.Client(system.endpoint) as client:
        assert {n.name for n in client.nodes()} == set(NODES)
        assert any(t.key == "robot/status" and t.type == "turtlectl/TurtleStatus" for t in client.topics())
        assert any(s.key == "navigate_to" and s.servers == ["navigator"] for s in client.services())


def test_topics_latest_iterated_and_called_back(system):
    with turtlectl.Client(system.endpoint) as client:
        assert isinstance(client.latest("robot/status"), TurtleStatus)

        sub = client.subscribe("robot/status")
        statuses = []
        for status in sub:
            statuses.append(status)
            if len(statuses) == 3:
                sub.undeclare()
        assert len(statuses) == 3 and not sub.active

        poses: list[Pose] = []
        three = threading.Event()

        def on_pose(pose: Pose) -> None:
            poses.append(pose)
            if len(poses) >= 3:
                three.set()

        handle = client.subscribe("turtle1/pose", on_pose)
        assert three.wait(10.0), "three poses by callback"
        handle.undeclare()

        start = client.latest("turtle1/pose")
        moved = client.subscribe("turtle1/pose")
        for _ in range(50):  # the sim's command timeout stops it: publish as a teleop does
            client.publish("turtle1/cmd_vel", Twist(linear=0.0, angular=1.0))
            if abs(moved.next(5.0).theta - start.theta) > 0.05:
                break
        else:
            pytest.fail("the turtle did not turn on our cmd_vel")
        moved.undeclare()
        client.publish("turtle1/cmd_vel", Twist(linear=0.0, angular=0.0))


def test_a_goal_with_its_feedback_then_cancel_with_nothing_running(system):
    feedback: list[NavigateToFeedback] = []
    with turtlectl.Client(system.endpoint) as client:
        response = client.goto(3.0, 3.0, 45.0, on_feedback=feedback.append)
        assert response.success, response
        assert feedback and all(isinstance(f, NavigateToFeedback) for f in feedback)
        assert client.cancel().ok is False


def test_a_goal_timed_out_or_canceled_raises_goal_canceled_with_the_final_pose_and_last_feedback(system):
    """One rule for a goal's cancel, whoever asks: the client's own timeout or a cancel."""
    system.teleport(1.0, 1.0, 0.0)
    with turtlectl.Client(system.endpoint) as client:
        with pytest.raises(turtlectl.GoalCanceled) as timed_out:
            client.goto(10.0, 1.0, 0.0, timeout=1.5)
        error = timed_out.value
        assert error.message == "the goal did not end within timeout=1.5 s; the navigator canceled the goal"
        assert error.exit_code == 1 and error.timeout == 1.5 and isinstance(error, turtlectl.Failed)
        assert error.response is not None and error.response.reason == "canceled", error.response
        assert isinstance(error.feedback, NavigateToFeedback) and error.feedback.x > 1.0
        assert error.response.x >= error.feedback.x > 1.0  # the final pose: where it stopped, past the last feedback
        system.wait_stopped()

        system.teleport(1.0, 1.0, 0.0)
        canceled: list[BaseException] = []

        def drive() -> None:
            try:
                client.goto(10.0, 1.0, 0.0)
            except turtlectl.GoalCanceled as exc:
                canceled.append(exc)

        driving = threading.Thread(target=drive)
        driving.start()
        system.wait_moving()
        assert client.cancel().ok
        driving.join(10.0)
        assert len(canceled) == 1, canceled
        error = canceled[0]
        assert error.message.startswith("the navigator canceled the goal") and error.timeout is None
        assert error.response.reason == "canceled" and error.response.x > 1.0
        assert isinstance(error.feedback, NavigateToFeedback)
        system.wait_stopped()


def test_parameters_read_set_and_refused(system):
    with turtlectl.Client(system.endpoint) as client:
        before = client.params("navigator")["goal_timeout"]
        client.set_param("navigator", "goal_timeout", before + 1)
        assert client.param("navigator", "goal_timeout") == before + 1
        with pytest.raises(turtlectl.BadInput, match="goal_timeout") as refused:
            client.set_param("navigator", "goal_timeout", -1)
        assert refused.value.exit_code == 2
        with pytest.raises(turtlectl.Unreachable) as nobody:
            client.params("nobody_here")
        assert nobody.value.exit_code == 3
        client.set_param("navigator", "goal_timeout", before)


def test_no_system_is_unreachable_exit_3_and_close_is_idempotent(system):
    with pytest.raises(turtlectl.Unreachable, match="no turtlectl system") as caught:
        turtlectl.Client(f"tcp/127.0.0.1:{free_port()}")
    assert caught.value.exit_code == 3
    client = turtlectl.Client(system.endpoint)
    sub = client.subscribe("robot/status")
    client.close()
    client.close()
    assert not sub.active and list(sub) == []


def test_a_script_that_ends_without_closing_its_client_ends(system):  # a hang: the subprocess timeout ends it
    """A script that subscribed with a callback and never closed its client ends after its last
    line (zenoh-python runs each callback subscriber on a Python thread of its own, not a daemon,
    which the interpreter would wait for at exit)."""
    import subprocess
    import sys

    script = (
        "import turtlectl\n"
        f"c = turtlectl.Client({system.endpoint!r})\n"
        "s = c.subscribe('turtles', callback=lambda m: None)\n"
        "print('end of script', flush=True)\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and done.stdout == "end of script\n", done.stdout + done.stderr


def test_no_message_names_the_key_read_not_the_key_as_written(system):
    """A client of turtle2 reads ``turtle1/pose`` as turtle2's pose: its error names that key."""
    with turtlectl.Client(system.endpoint, turtle="turtle2") as client:
        with pytest.raises(turtlectl.Failed, match=r"^no message on turtle2/pose within 0.5 s$"):
            client.latest("turtle1/pose", timeout=0.5)


def test_a_node_that_does_not_run_is_said_as_the_command_line_says_it(system):
    with turtlectl.Client(system.endpoint) as client:
        with pytest.raises(turtlectl.Unreachable) as raised:
            client.param("navigatr", "goal_timeout")
    said = str(raised.value)
    assert said.startswith("no node named 'navigatr' answers; did you mean navigator? (running: "), said
    assert raised.value.exit_code == 3
    cli = system.run_cli("param", "get", "navigatr", "goal_timeout", "--connect", system.endpoint)
    assert (cli.returncode, cli.stderr.strip()) == (3, f"turtlectl: error: {said}")
