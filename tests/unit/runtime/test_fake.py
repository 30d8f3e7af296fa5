"""runtime.fake: a node class unit-tested without Zenoh, through the real ``Node`` code on a
fake clock and an in-memory session."""

from __future__ import annotations

import logging
from typing import Annotated, Any, ClassVar

import msgspec
import pytest

from turtlectl.messages import Ack, ErrorReply, Message, ParameterEvent, Pose, Reset, Twist
from turtlectl.messages.keys import PARAMETER_EVENTS, param_set_key, params_key
from turtlectl.runtime.config import Interface
from turtlectl.runtime.entities import Timer
from turtlectl.runtime.fake import FakeNode
from turtlectl.runtime.interface import OutsideInterface
from turtlectl.runtime.node import Node


class CounterParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    FIXED: ClassVar[dict[str, str]] = {"period": "the timer is made once"}

    step: Annotated[float, msgspec.Meta(gt=0.0)] = 1.0  # m/s: added at each tick
    period: float = 0.1  # s: between ticks


class Counter:
    """Everything a node does: publisher, timer, subscription, latest, service, call,
    liveliness watch, parameter hook, shutdown hook."""

    Params = CounterParams
    Interface = Interface(
        publishes=("demo/count",),
        subscribes=("demo/cmd", "demo/pose"),
        serves=("demo/reset",),
        calls=("demo/other",),
        watches=("demo/alive/*",),
    )

    def __init__(self, node: Node[CounterParams]):
        self.node = node
        self.ticks = 0
        self.heard: list[Twist] = []
        self.live: list[tuple[str, bool]] = []
        self.answers: list[list[Message]] = []
        self.steps: list[float] = []
        self.stopped = False
        self.pub = node.publisher("demo/count", Twist)
        self.timer = node.timer(node.params.period, self.tick)
        self.sub = node.subscribe("demo/cmd", Twist, self.hear)
        self.pose = node.latest("demo/pose", Pose)
        self.srv = node.serve("demo/reset", Reset, Ack, self.reset)
        node.watch_liveliness("demo/alive/*", lambda key, alive: self.live.append((key, alive)))
        node.on_params(lambda params: self.steps.append(params.step))
        node.on_shutdown(self.stop)

    def tick(self) -> None:
        self.ticks += 1
        self.pub.publish(Twist(linear=self.node.params.step * self.ticks))

    def hear(self, msg: Twist) -> None:
        if msg.linear < 0:
            raise RuntimeError("cannot go backwards")
        self.heard.append(msg)
        if msg.angular:
            self.node.call("demo/other", Reset(), self.answers.append)

    def reset(self, request: Any) -> None:
        self.ticks = 0
        request.respond(Ack(detail="reset"))

    def stop(self) -> None:
        self.stopped = True
        self.pub.publish(Twist())


def test_timers_fire_on_the_fake_clock_each_at_its_own_deadline():
    fake = FakeNode(Counter, {"step": 0.5})
    assert fake.now == 0.0 and fake.instance.ticks == 0
    fake.advance(0.35)
    assert fake.instance.ticks == 3 and fake.now == pytest.approx(0.35)
    assert [m.linear for m in fake.published("demo/count")] == [0.5, 1.0, 1.5]
    assert [m.seq for m in fake.published("demo/count")] == [0, 1, 2]
    fake.advance(0.05)  # 0.4: the 4th tick, rounding or not
    assert fake.instance.ticks == 4
    fake.instance.timer.pause()
    fake.advance(0.95)
    assert fake.instance.ticks == 4
    fake.instance.timer.resume()  # now=None: the node's clock (1.35), the fake one: next tick at 1.4
    fake.advance(0.04)
    assert fake.instance.ticks == 4
    fake.advance(0.02)
    assert fake.instance.ticks == 5


def test_three_advances_of_a_period_give_three_ticks():
    fake = FakeNode(Counter)
    for _ in range(3):
        fake.advance(0.1)
    assert fake.instance.ticks == 3


def test_a_delivered_message_reaches_the_callback_and_latest():
    fake = FakeNode(Counter)
    fake.deliver("demo/cmd", Twist(linear=2.0))
    assert [m.linear for m in fake.instance.heard] == [2.0]
    assert fake.instance.pose.get() is None
    fake.deliver("demo/pose", Pose(x=1.0, y=2.0, theta=0.0))
    assert fake.instance.pose.get() == Pose(x=1.0, y=2.0, theta=0.0)
    fake.deliver("elsewhere", Twist(linear=9.0))  # nobody subscribes: nothing
    assert len(fake.instance.heard) == 1


def test_garbage_is_logged_and_dropped_and_the_node_keeps_running(caplog):
    fake = FakeNode(Counter)
    with caplog.at_level(logging.WARNING):
        fake.deliver("demo/cmd", b"\x01garbage")
        fake.deliver("demo/pose", Twist())  # the wrong type: garbage for a Pose
        assert fake.instance.pose.get() is None  # a latest value is decoded (and garbage logged) when read
    assert "dropped malformed payload #1 on demo/cmd" in caplog.text
    assert "dropped malformed payload #1 on demo/pose" in caplog.text
    assert fake.instance.heard == []
    fake.deliver("demo/cmd", Twist(linear=1.0))
    fake.advance(0.1)
    assert len(fake.instance.heard) == 1 and fake.instance.ticks == 1


def test_a_latest_value_is_read_newest_first_its_garbage_logged_when_read(caplog):
    """A latest value's samples wait in a ring channel (Zenoh keeps them, Python is not
    woken for each): read, every one that came is decoded oldest first, garbage counted and
    logged even when a valid sample followed it, the newest valid one kept."""
    fake = FakeNode(Counter)
    with caplog.at_level(logging.WARNING):
        fake.deliver("demo/pose", b"\x01garbage")
        fake.deliver("demo/pose", Pose(x=1.0, y=2.0, theta=0.0))
        assert "malformed" not in caplog.text  # nothing is decoded before it is read
        assert fake.instance.pose.get() == Pose(x=1.0, y=2.0, theta=0.0)
        assert "dropped malformed payload #1 on demo/pose" in caplog.text
        fake.deliver("demo/pose", b"\x01garbage")
        assert fake.instance.pose.get() == Pose(x=1.0, y=2.0, theta=0.0)
    assert "dropped malformed payload #2 on demo/pose" not in caplog.text  # counted, logged 1st and every 100th
    assert fake.node.core.rejections()["demo/pose"] == 2


def test_a_request_gets_its_reply_and_garbage_an_error_reply():
    fake = FakeNode(Counter)
    fake.advance(0.25)
    assert fake.request("demo/reset", Reset()) == [Ack(detail="reset")]
    assert fake.instance.ticks == 0
    (error,) = fake.request("demo/reset", b"\x01garbage")
    assert isinstance(error, ErrorReply) and "not a valid turtlectl/Reset" in error.error
    assert fake.request(params_key(fake.node.name)) == [{"step": 1.0, "period": 0.1}]  # a JSON answer
    assert fake.request("demo/nobody", Reset()) == []


def test_a_call_is_answered_by_what_the_test_registered_or_by_nobody():
    fake = FakeNode(Counter)
    fake.deliver("demo/cmd", Twist(angular=1.0))
    assert fake.instance.answers == [[]]  # nobody serves demo/other: done at once, no replies
    fake.answer("demo/other", lambda request: [Ack(detail=f"got {type(request).__name__}")])
    fake.deliver("demo/cmd", Twist(angular=1.0))
    assert fake.instance.answers[1] == [Ack(detail="got Reset")]


def test_liveliness_tokens_appear_and_vanish():
    fake = FakeNode(Counter)
    fake.liveliness("demo/alive/a", True)
    fake.liveliness("other/b", True)
    fake.liveliness("demo/alive/a", False)
    assert fake.instance.live == [("demo/alive/a", True), ("demo/alive/a", False)]


def test_a_parameter_set_runs_the_hooks_and_a_refused_one_gives_an_error_reply():
    fake = FakeNode(Counter)
    assert fake.set_param("step", 2) == Ack(detail=f"{fake.node.name} step = 2.0 (was 1.0)")
    assert fake.node.params.step == 2.0 and fake.instance.steps == [2.0]
    (event,) = fake.published(PARAMETER_EVENTS)
    assert isinstance(event, ParameterEvent) and (event.old_value, event.new_value) == (1.0, 2.0)
    refused = fake.set_param("step", -1.0)
    assert isinstance(refused, ErrorReply) and "step" in refused.error
    fixed = fake.set_param("period", 1.0)
    assert isinstance(fixed, ErrorReply) and "cannot change at run time" in fixed.error
    assert fake.instance.steps == [2.0]
    assert fake.request(param_set_key(fake.node.name), msgspec.json.encode({"x": 1})) != []  # garbage: refused


def test_undeclared_entities_are_gone():
    fake = FakeNode(Counter)
    fake.instance.sub.undeclare()
    fake.instance.srv.undeclare()
    fake.instance.timer.undeclare()
    fake.instance.pub.undeclare()
    fake.deliver("demo/cmd", Twist(linear=1.0))
    fake.advance(1.0)
    assert fake.instance.heard == [] and fake.instance.ticks == 0
    assert fake.request("demo/reset", Reset()) == []  # nobody serves it any more


def test_an_exception_in_node_code_propagates_to_the_test():
    fake = FakeNode(Counter)
    with pytest.raises(RuntimeError, match="cannot go backwards"):
        fake.deliver("demo/cmd", Twist(linear=-1.0))
    fake.deliver("demo/cmd", Twist(linear=1.0))  # the queue was not left half-run
    assert len(fake.instance.heard) == 1


def test_shutdown_runs_the_hooks_once_and_the_context_manager_does_it():
    with FakeNode(Counter, name="counter") as fake:
        assert fake.node.name == "counter"
    assert fake.instance.stopped and fake.node.stopping
    assert fake.published_all()[-1] == ("demo/count", Twist(seq=0, stamp=fake.published_all()[-1][1].stamp))
    fake.shutdown()  # twice: nothing more
    assert len(fake.published_all()) == 1


def test_params_are_validated_into_the_node_class_params():
    assert FakeNode(Counter, CounterParams(step=3.0)).node.params.step == 3.0
    assert FakeNode(Counter).node.name == "counter"  # named after its class, as `turtlectl run` does
    with pytest.raises(ValueError, match="step"):
        FakeNode(Counter, {"step": -1.0})
    with pytest.raises(ValueError, match="nope"):
        FakeNode(Counter, {"nope": 1})


def test_a_timer_reads_the_clock_it_was_given():
    now = [100.0]
    t = Timer(0.1, lambda: None, 100.0, clock=lambda: now[0])
    now[0] = 100.23
    t.retime(0.5)
    assert t.deadline == pytest.approx(100.73)
    t.pause()
    now[0] = 101.5
    t.resume()
    assert t.deadline == pytest.approx(101.73)


class Talker:
    """Publishes what its Interface does not name: refused at once."""

    Params = CounterParams
    Interface = Interface(publishes=("chatter",))

    def __init__(self, node: Node[CounterParams]):
        node.publisher("chatter", Twist)
        node.publisher("robot/alarm", Twist)


class Undeclared:
    """No Interface: what a teleop client may do (cmd_vel, subscribe to all) and its own name's keys."""

    Params = CounterParams

    def __init__(self, node: Node[CounterParams]):
        node.publisher("turtle1/cmd_vel", Twist)
        node.publisher("undeclared/state", Twist)
        node.subscribe("anything/at/all", Twist, print)
        node.serve("robot/reset_all", Reset, Ack, print)


def test_a_declaration_outside_the_interface_is_refused_at_once():
    with pytest.raises(OutsideInterface, match=r"talker may not publish robot/alarm: its Interface publishes chatter"):
        FakeNode(Talker)
    with pytest.raises(
        OutsideInterface, match=r"undeclared may not serve robot/reset_all: its Interface serves undeclared/\*\*"
    ):
        FakeNode(Undeclared)


class Driver:
    """Publishes one Twist a tick."""

    Params = msgspec.defstruct("DriverParams", [])

    def __init__(self, node: Node[Any]):
        self.pub = node.publisher("turtle1/cmd_vel", Twist)
        node.timer(0.1, lambda: self.pub.publish(Twist(linear=1.0, angular=0.5)))


def test_a_published_message_equals_the_one_built_by_hand_once_unstamped():
    from turtlectl.testing import unstamped  # the public name

    fake = FakeNode(Driver)
    fake.advance(0.2)
    sent = fake.published("turtle1/cmd_vel")
    assert sent[0] != Twist(linear=1.0, angular=0.5)  # the publisher filled in stamp and seq
    assert [m.seq for m in sent] == [0, 1] and sent[0].stamp > 0
    assert [unstamped(m) for m in sent] == [Twist(linear=1.0, angular=0.5)] * 2
    assert unstamped(Ack(ok=True)) == Ack(ok=True)  # nothing to take out of an unstamped type
