"""The goal server and client (runtime.goals, runtime.goal_client) on FakeNode and a fake clock:
refusal, preemption, cancel, the caller going away, the deadline, feedback at a rate, shutdown,
exactly one result per goal; the client's future, feedback and cancel."""

from __future__ import annotations

import msgspec
import pytest

from turtlectl.messages import Ack, Cancel, Message
from turtlectl.messages.keys import parse_entity_token
from turtlectl.runtime.config import Interface
from turtlectl.runtime.fake import FakeNode
from turtlectl.runtime.futures import FutureError
from turtlectl.runtime.goal_client import GoalFailed


class Laps(Message, tag="TestLaps"):
    laps: int


class LapsFeedback(Message, tag="TestLapsFeedback"):
    done: int


class LapsResult(Message, tag="TestLapsResult"):
    success: bool = False
    reason: str = ""
    laps: int = 0


class LapperParams(msgspec.Struct, frozen=True):
    timeout: float = 10.0  # s: how long a goal may run


class Lapper:
    """One lap a second; refuses no laps; says how many at 2 Hz."""

    Params = LapperParams

    def __init__(self, node):
        self.node = node
        self.laps = 0
        self.ended: list[tuple[int, str]] = []  # (laps asked, why) of each goal the server ended
        self.details: list[str] = []  # the canceller's words of each (Cancel.detail), "" if none
        self.server = node.goal_server(
            "lapper/laps",
            Laps,
            LapsFeedback,
            LapsResult,
            execute=self.execute,
            refuse=self.refuse,
            on_cancel=self.on_cancel,
            feedback=lambda goal: LapsFeedback(done=self.laps),
            feedback_rate=2.0,
            timeout=node.params.timeout,
        )
        node.timer(1.0, self.lap)
        node.on_params(lambda params: setattr(self.server, "timeout", params.timeout))

    def refuse(self, goal: Laps) -> LapsResult | None:
        return LapsResult(reason="no laps") if goal.laps <= 0 else None

    def execute(self, goal) -> None:
        self.laps = 0

    def on_cancel(self, goal, reason: str) -> LapsResult:
        self.ended.append((goal.request.laps, reason))
        self.details.append(goal.end_detail)
        return LapsResult(reason=reason, laps=self.laps)

    def lap(self) -> None:
        goal = self.server.goal
        if goal is not None:
            self.laps += 1
            if self.laps >= goal.request.laps:
                goal.finish(LapsResult(success=True, laps=self.laps))


KEY = "lapper/laps"


def test_a_goal_runs_with_feedback_at_its_rate_then_one_result():
    with FakeNode(Lapper) as fake:
        goal = fake.send_goal(KEY, Laps(laps=3))
        assert goal.result is None and [f.done for f in goal.feedback] == [0]  # at once: the goal runs
        fake.advance(2.9)
        assert [f.done for f in goal.feedback] == [
            0,
            0,
            0,
            1,
            1,
            2,
        ]  # then 2 Hz: at 0.5, ... 2.5 s (before that second's lap)
        fake.advance(0.1)
        assert goal.result == LapsResult(success=True, laps=3)
        # observers see the same feedback, stamped as the caller's
        assert fake.published(f"{KEY}/feedback") == goal.feedback
        fake.advance(5.0)
        assert len(goal.replies) == 8 and fake.instance.server.goal is None  # nothing after the result


def test_a_refusal_is_the_only_reply_and_leaves_the_running_goal_alone():
    with FakeNode(Lapper) as fake:
        running = fake.send_goal(KEY, Laps(laps=5))
        fake.advance(1.0)
        refused = fake.send_goal(KEY, Laps(laps=0), client="other")
        assert refused.result == LapsResult(reason="no laps") and refused.feedback == []
        assert fake.instance.server.goal is not None and fake.instance.ended == []
        fake.advance(4.0)
        assert running.result == LapsResult(success=True, laps=5)


def test_a_newer_goal_preempts_the_running_one():
    with FakeNode(Lapper) as fake:
        first = fake.send_goal(KEY, Laps(laps=5), client="first")
        fake.advance(1.0)
        second = fake.send_goal(KEY, Laps(laps=1), client="second")
        assert first.result == LapsResult(reason="preempted", laps=1)
        assert fake.instance.ended == [(5, "preempted")]
        fake.advance(1.0)
        assert second.result == LapsResult(success=True, laps=1)


def test_cancel_ends_the_goal_with_the_cancels_reason_and_acknowledges():
    with FakeNode(Lapper) as fake:
        goal = fake.send_goal(KEY, Laps(laps=5))
        fake.advance(1.0)
        assert goal.cancel() == Ack(detail="canceled the goal (5)")
        assert goal.result == LapsResult(reason="canceled", laps=1)
        assert goal.cancel() == Ack(ok=False, detail="no goal is running")
        again = fake.send_goal(KEY, Laps(laps=5))
        assert again.cancel("teleported").ok and again.result.reason == "teleported"


def test_the_cancels_detail_reaches_on_cancel_with_the_goal():
    """A canceller's own words (``Cancel.detail``) are the goal's ``end_detail`` when on_cancel runs."""
    with FakeNode(Lapper) as fake:
        goal = fake.send_goal(KEY, Laps(laps=5))
        replies = fake.request(f"{KEY}/cancel", Cancel(reason="teleop", detail="the keyboard took over"))
        assert replies[0].ok and fake.instance.details == ["the keyboard took over"] and goal.result.reason == "teleop"


def test_a_caller_that_goes_away_has_its_goal_ended_and_no_other_caller_does():
    with FakeNode(Lapper) as fake:
        goal = fake.send_goal(KEY, Laps(laps=5), client="abc")
        fake.liveliness("@turtlectl/client/other", False)
        assert goal.result is None
        goal.caller_gone()
        assert goal.result == LapsResult(reason="caller gone")


def test_a_goal_type_with_a_client_field_names_its_caller_there():
    class Named(Message, tag="TestNamedGoal"):
        laps: int
        client: str = ""

    class Server:
        Params = LapperParams

        def __init__(self, node):
            self.server = node.goal_server(KEY, Named, LapsFeedback, LapsResult, execute=lambda goal: None)

    with FakeNode(Server, name="lapper") as fake:
        replies = fake.request(KEY, Named(laps=1, client="xyz"))
        assert fake.instance.server.goal.caller == "@turtlectl/client/xyz"
        fake.liveliness("@turtlectl/client/xyz", False)
        assert replies == [LapsResult(reason="caller gone")]  # the default result: success=False, reason


def test_the_deadline_ends_the_goal_and_can_change_while_it_runs():
    with FakeNode(Lapper, {"timeout": 2.5}) as fake:
        goal = fake.send_goal(KEY, Laps(laps=10))
        fake.advance(2.49)
        assert goal.result is None
        fake.advance(0.02)
        assert goal.result == LapsResult(reason="timeout", laps=2)
        goal = fake.send_goal(KEY, Laps(laps=10))
        fake.advance(1.0)
        assert fake.set_param("timeout", 4.0).ok  # the running goal's deadline moves: 4 s from its start
        fake.advance(2.9)
        assert goal.result is None
        fake.advance(0.2)
        assert goal.result is not None and goal.result.reason == "timeout"


def test_shutdown_ends_the_running_goal_once():
    fake = FakeNode(Lapper)
    goal = fake.send_goal(KEY, Laps(laps=5))
    fake.shutdown()
    assert goal.result == LapsResult(reason="shut down")
    fake.shutdown()
    assert len(goal.replies) == 2  # the feedback at its start, then one result


def test_a_goal_has_exactly_one_result():
    with FakeNode(Lapper) as fake:
        goal = fake.send_goal(KEY, Laps(laps=5))
        handle = fake.instance.server.goal
        assert handle.finish(LapsResult(success=True)) and not handle.finish(LapsResult(reason="again"))
        assert handle.feedback(LapsFeedback(done=1)) is None
        assert goal.replies == [LapsFeedback(done=0), LapsResult(success=True)]  # its first feedback, one result
        with pytest.raises(TypeError):
            fake.send_goal(KEY, Laps(laps=5))
            fake.instance.server.goal.finish(LapsFeedback(done=1))


def test_undeclaring_ends_the_goal_and_withdraws_the_service():
    with FakeNode(Lapper) as fake:
        goal = fake.send_goal(KEY, Laps(laps=5))
        fake.instance.server.undeclare()
        assert goal.result == LapsResult(reason="shut down")
        assert fake.request(KEY, Laps(laps=1)) == []
        fake.instance.server.undeclare()


def test_the_goal_service_is_in_the_graph_with_its_three_types():
    with FakeNode(Lapper) as fake:
        entities = [e for t in fake.session.tokens if (e := parse_entity_token(t.key)) is not None]
        roles = {e.role: e.type_name for e in entities if e.key == KEY}
        assert roles == {"srv": "tests/TestLaps", "goal": "tests/TestLaps", "goal_feedback": "tests/TestLapsFeedback",
                         "goal_result": "tests/TestLapsResult"}  # fmt: skip


def test_without_on_cancel_a_result_type_that_needs_more_is_refused_when_declared():
    class Strict(Message, tag="TestStrictResult"):
        laps: int

    class Server:
        Params = LapperParams

        def __init__(self, node):
            node.goal_server(KEY, Laps, LapsFeedback, Strict, execute=lambda goal: None)

    with pytest.raises(TypeError, match="on_cancel"):
        FakeNode(Server, name="lapper")


# -- the client side: futures ------------------------------------------------------------------
CALLS = Interface(calls=("lapper/**",))


class Caller:
    Params = LapperParams
    Interface = CALLS

    def __init__(self, node):
        self.node = node
        self.client = node.goal_client(KEY, Laps, LapsFeedback, LapsResult)
        self.feedback: list[LapsFeedback] = []
        self.said: list[str] = []


def test_a_node_sends_a_goal_gets_feedback_and_the_result_as_a_future():
    with FakeNode(Caller, name="caller") as fake:
        fake.answer(KEY, lambda goal: [LapsFeedback(done=1), LapsResult(success=True, laps=goal.laps)])
        caller = fake.instance
        future = caller.client.send(Laps(laps=2), on_feedback=caller.feedback.append)
        future.then(lambda result: f"{result.laps} laps").add_done_callback(lambda f: caller.said.append(f.result()))
        assert not future.done()
        with pytest.raises(FutureError, match="then"):  # waiting on the node's own thread would never end
            future.result()
        fake.advance(0.0)
        assert caller.feedback == [LapsFeedback(done=1)]
        assert future.result() == LapsResult(success=True, laps=2) and caller.said == ["2 laps"]
        # its caller token is held, and the goal names it (the attachment)
        assert any(t.key == f"@turtlectl/client/{caller.client.client_id}" for t in fake.session.tokens)


def test_a_goal_nobody_serves_fails_its_future_and_cancel_gets_the_ack():
    with FakeNode(Caller, name="caller") as fake:
        future = fake.instance.client.send(Laps(laps=2))
        fake.advance(0.0)
        assert isinstance(future.exception(), GoalFailed)
        fake.answer(f"{KEY}/cancel", lambda request: [Ack(detail=f"canceled: {request.reason}")])
        ack = fake.instance.client.cancel("enough")
        fake.advance(0.0)
        assert ack.result() == Ack(detail="canceled: enough")


def test_node_call_returns_a_future_and_keeps_the_callback_form():
    class Asker:
        Params = LapperParams
        Interface = CALLS

        def __init__(self, node):
            self.node = node
            self.got: list[object] = []

        def ask(self):
            self.node.call("lapper/other", Laps(laps=1), self.got.append)
            calls = self.node.call("lapper/other", Laps(laps=2))
            calls.then(len).add_done_callback(lambda f: self.got.append(f.result()))

    with FakeNode(Asker, name="lapper") as fake:
        fake.answer("lapper/other", lambda request: [Ack(detail=str(request.laps))])
        fake.instance.ask()
        fake.advance(0.0)
        assert fake.instance.got == [[Ack(detail="1")], 1]


def test_a_goal_whose_server_goes_away_ends_naming_it_and_the_node_says_so_once(caplog):
    server = f"@turtlectl/entity/lapper/4242/goal/test.TestLaps/{KEY}"
    with FakeNode(Caller, name="caller") as fake:
        fake.liveliness(server, True)
        fake.session.get = lambda *args, **kwargs: None  # the goal's query stays open, as a long goal's does
        future = fake.instance.client.send(Laps(laps=9))
        with caplog.at_level("INFO"):
            fake.liveliness(server, False)
            fake.liveliness(server, False)  # said once
            fake.advance(0.0)
            assert isinstance(future.exception(), GoalFailed)
            assert str(future.exception()) == f"{KEY}'s server lapper (pid 4242) went away before the goal ended"
            fake.liveliness(f"@turtlectl/entity/lapper/4343/goal/test.TestLaps/{KEY}", True)
        said = [r.getMessage() for r in caplog.records if KEY in r.getMessage()]
        assert said == [
            f"{KEY}'s server lapper (pid 4242) went away (it exited, or its host is cut off): "
            "goals to it fail until it is back",
            f"{KEY} is served again: lapper (pid 4343) is back",
        ]
