"""A student's own navigator on the goal server (Node.goal_server), launched beside the built-in
simulator from a project folder of its own: ``turtlectl goto`` drives it with feedback, Ctrl-C
cancels it (exit 130, the turtle stops), a newer goal preempts; a patrol's own goal service
(its own Laps types) is listed by ``action list`` and driven by ``action send-goal --feedback``
and ``Client.send_goal``."""

from __future__ import annotations

import select
import signal
import subprocess
import textwrap

import pytest

from tests.integration.harness import running_system, turtlectl

pytestmark = pytest.mark.integration

NAVIGATOR = textwrap.dedent(
    '''
    """A go-to-goal P-controller on the goal server, and a patrol with a goal of its own."""

    import math

    import msgspec

    from turtlectl import Interface, Message, Node
    from turtlectl.messages import GoalState, NavigateToFeedback, NavigateToRequest, NavigateToResponse, Pose, Twist


    class GoToParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
        speed: float = 1.5  # m/s: the fastest it drives


    class GoToGoal:
        Params = GoToParams
        Interface = Interface(
            publishes=("turtle1/cmd_vel", "navigate_to/feedback"),
            subscribes=("turtle1/pose",),
            serves=("navigate_to", "navigate_to/cancel"),
            watches=("@turtlectl/client/**",),
        )

        def __init__(self, node: Node[GoToParams]):
            self.node = node
            self.cmd = node.publisher("turtle1/cmd_vel", Twist)
            self.pose = None
            node.subscribe("turtle1/pose", Pose, self.on_pose)
            self.server = node.goal_server(
                "navigate_to", NavigateToRequest, NavigateToFeedback, NavigateToResponse,
                execute=lambda goal: None, on_cancel=self.on_cancel, feedback=self.progress, timeout=60.0,
            )

        def on_pose(self, pose):
            self.pose = pose
            goal = self.server.goal
            if goal is None:
                return
            dx, dy = goal.request.x - pose.x, goal.request.y - pose.y
            distance = math.hypot(dx, dy)
            if distance < 0.05:
                self.cmd.publish(Twist())
                goal.finish(self.result(goal, True))
                return
            error = math.atan2(math.sin(math.atan2(dy, dx) - pose.theta), math.cos(math.atan2(dy, dx) - pose.theta))
            linear = min(self.node.params.speed, 1.5 * distance) if abs(error) < 0.3 else 0.0
            self.cmd.publish(Twist(linear=linear, angular=4.0 * error))

        def progress(self, goal):
            if self.pose is None:
                return None
            p = self.pose
            distance = math.hypot(goal.request.x - p.x, goal.request.y - p.y)
            return NavigateToFeedback(
                state=GoalState.DRIVING, distance_remaining=distance, heading_remaining=0.0, eta=distance,
                elapsed=self.node.clock() - goal.started, x=p.x, y=p.y, theta=math.degrees(p.theta) % 360,
            )

        def result(self, goal, success, reason=""):
            p = self.pose
            return NavigateToResponse(
                success=success, reason=reason, time_taken=self.node.clock() - goal.started,
                x=p.x if p else 0.0, y=p.y if p else 0.0,
            )

        def on_cancel(self, goal, reason):
            self.cmd.publish(Twist())
            return self.result(goal, False, reason)


    class Laps(Message, tag="StudentLaps"):
        laps: int


    class LapsDone(Message, tag="StudentLapsDone"):
        done: int


    class LapsResult(Message, tag="StudentLapsResult"):
        success: bool = False
        reason: str = ""
        laps: int = 0


    class Patrol:
        Params = GoToParams

        def __init__(self, node):
            self.done = 0
            self.server = node.goal_server(
                "patrol/laps", Laps, LapsDone, LapsResult, execute=self.start,
                feedback=lambda goal: LapsDone(done=self.done), feedback_rate=5.0,
            )
            node.timer(0.3, self.lap)

        def start(self, goal):
            self.done = 0

        def lap(self):
            goal = self.server.goal
            if goal is not None:
                self.done += 1
                if self.done >= goal.request.laps:
                    goal.finish(LapsResult(success=True, laps=self.done))
    '''
)

LAUNCH = textwrap.dedent(
    """
    [[node]]
    name = "sim"
    run = "sim"

    [[node]]
    name = "mynav"
    run = "./mynav.py:GoToGoal"

    [[node]]
    name = "patrol"
    run = "./mynav.py:Patrol"
    """
)


@pytest.fixture(scope="module")
def system(tmp_path_factory):
    project = tmp_path_factory.mktemp("student")
    (project / "mynav.py").write_text(NAVIGATOR)
    (project / "launch.toml").write_text(LAUNCH)
    with running_system(project / "launch.toml", ready=("sim", "mynav", "patrol"), cwd=project) as system:
        yield system


def test_goto_drives_a_students_navigator_with_feedback(system):
    done = system.run_cli("goto", "7", "5", "0", "--timeout", "30", timeout=40)
    assert done.returncode == 0, done.stdout + done.stderr


def test_ctrl_c_on_goto_cancels_and_the_turtle_stops(system):
    goto = subprocess.Popen(
        [*turtlectl(), "goto", "2", "2", "0", "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        system.wait_moving()
        goto.send_signal(signal.SIGINT)
        goto.wait(10)
        err = goto.stderr.read()
        assert goto.returncode == 130 and "interrupted: the navigator canceled the goal" in err, err
        system.wait_stopped()
    finally:
        goto.kill()


def test_a_newer_goal_preempts_the_running_one(system):
    first = subprocess.Popen(
        [*turtlectl(), "goto", "9", "9", "0", "--json", "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        system.wait_moving()
        second = system.run_cli("goto", "5", "5", "0", "--timeout", "30", timeout=40)
        out, err = first.communicate(timeout=10)
        assert first.returncode == 1 and "preempted" in out + err, out + err
        assert second.returncode == 0, second.stdout + second.stderr
    finally:
        first.kill()


def test_action_list_info_and_send_goal_reach_a_patrols_own_goal_service(system):
    listed = system.run_cli("action", "list")
    assert listed.returncode == 0, listed.stderr
    assert "patrol/laps  [mynav/StudentLaps -> mynav/StudentLapsDone -> mynav/StudentLapsResult]" in listed.stdout
    assert "navigate_to" in listed.stdout
    info = system.run_cli("action", "info", "patrol/laps")
    assert "Servers: patrol" in info.stdout, info.stdout + info.stderr
    sent = system.run_cli("action", "send-goal", "patrol/laps", '{"laps": 3}', "--feedback", "--json")
    assert sent.returncode == 0, sent.stdout + sent.stderr
    assert '"done"' in sent.stdout and '"laps":3' in sent.stdout.replace(" ", "")


def test_client_send_goal_returns_a_future_with_feedback(system):
    from turtlectl import Client

    with Client(system.endpoint) as client:
        feedback = []
        future = client.send_goal("patrol/laps", _laps(client, 2), on_feedback=feedback.append)
        result = future.result(timeout=10)
        assert result.success and result.laps == 2 and feedback


def _laps(client, n):
    """The patrol's own goal type, as the client learnt it from the nodes."""
    from turtlectl.cli.tools import build
    from turtlectl.runtime.client.typebook import TypeBook

    TypeBook(client.session).learn_all()
    return build.message_from_json(f'{{"laps": {n}}}', build.type_named("StudentLaps"))


def test_ctrl_c_on_send_goal_names_the_goal_service_and_its_node_not_the_navigator(system):
    sent = subprocess.Popen(
        [*turtlectl(), "action", "send-goal", "patrol/laps", '{"laps": 1000}', "--feedback", "--json"]
        + ["--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert select.select([sent.stdout], [], [], 10.0)[0], "no feedback within 10 s"
        assert '"done"' in sent.stdout.readline()  # the goal runs: its first feedback
        sent.send_signal(signal.SIGINT)
        sent.wait(10)
        err = sent.stderr.read()
        assert sent.returncode == 130, err
        assert err.strip() == "turtlectl: interrupted: the goal service patrol/laps (patrol) canceled the goal"
    finally:
        sent.kill()
