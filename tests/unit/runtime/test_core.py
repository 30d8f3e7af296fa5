"""The node's core (runtime.core.NodeCore): a new declaration kind is one module (the ``echo``
kind below is all of one), and the core's contract: its queue, timers, time source and one
declaration path, driven as ``Node`` and ``FakeNode`` drive it."""

from __future__ import annotations

import logging
import threading
import time

import msgspec
import pytest
import zenoh

from turtlectl.messages import Pose, decode, encode
from turtlectl.messages.keys import parse_entity_token
from turtlectl.runtime.config import Interface, NodeConfig
from turtlectl.runtime.core import Kind, NodeCore
from turtlectl.runtime.fake import FakeNode, FakeSession
from turtlectl.runtime.handles import Declaration
from turtlectl.runtime.interface import OutsideInterface
from turtlectl.runtime.node import Node

# -- a new declaration kind, whole: a Kind and a function over the node's core -----------------

#: a service answering each request with the request itself (the interface's "serve"; one graph
#: token, "srv", with the request's type)
ECHO = Kind("echo", "serve", ("srv",))


def echo(node: Node, key: str, msg_type: type[msgspec.Struct]) -> Declaration:
    """Answer each ``msg_type`` query on ``key`` with the request, from the node's thread."""
    core = node.core

    def build(declared: Declaration) -> Declaration:
        def on_query(query: zenoh.Query) -> None:  # Zenoh thread: queue only
            core.enqueue(answer, query)

        def answer(query: zenoh.Query) -> None:
            if declared.active:  # queued before it was undeclared: nothing
                query.reply(declared.key, query.payload.to_bytes())

        declared.add(core.session.declare_queryable(declared.key, on_query))
        return declared

    return core.declare(ECHO, key, (msg_type,), build)


class NoParams(msgspec.Struct):
    pass


class Echoer:
    Params = NoParams
    Interface = Interface(serves=("toy/echo",))

    def __init__(self, node: Node):
        self.echo = echo(node, "toy/echo", Pose)


def test_a_new_kind_declared_through_the_core_is_checked_served_shown_and_undeclared():
    fake = FakeNode(Echoer)
    pose = Pose(x=1.0, y=2.0, theta=0.5)
    assert fake.request("toy/echo", pose) == [pose]
    tokens = [parse_entity_token(t.key) for t in fake.session.tokens]
    assert ("echoer", "srv", "toy/echo", "turtlectl/Pose") in [(t.node, t.role, t.key, t.type_name) for t in tokens]
    fake.instance.echo.undeclare()
    assert fake.request("toy/echo", pose) == []
    assert "toy/echo" not in [parse_entity_token(t.key).key for t in fake.session.tokens]
    with pytest.raises(OutsideInterface, match="echoer may not serve toy/other"):
        echo(fake.node, "toy/other", Pose)


def test_the_runtimes_own_declarations_pass_whatever_the_interface():
    fake = FakeNode(Echoer)
    declared = fake.node.core.declare(ECHO, "echoer/own", (), lambda d: d, own=True)
    assert declared.active and declared.key == "echoer/own"
    with pytest.raises(OutsideInterface):
        fake.node.core.declare(ECHO, "echoer/own2", (), lambda d: d)


# -- the core's contract ------------------------------------------------------------------------


def core_on(clock: list[float]) -> NodeCore:
    return NodeCore("toy", FakeSession(), logging.getLogger("toy"), lambda: clock[0], lambda: 7)


def test_queued_callbacks_run_in_order_and_what_they_queue_runs_in_the_same_drain():
    core = core_on([0.0])
    ran: list[str] = []
    core.enqueue(ran.append, "a")
    core.enqueue(lambda: (ran.append("b"), core.enqueue(ran.append, "c")))
    assert core.pending() == 2
    core.drain()
    assert ran == ["a", "b", "c"] and core.pending() == 0


def test_timers_fire_when_due_each_once_on_their_grid_and_a_time_source_swaps_clock_and_stamps():
    now = [10.0]
    core = core_on(now)
    fired: list[float] = []
    timer = core.timer(0.5, lambda: fired.append(now[0]))
    assert core.next_deadline() == 10.5
    core.fire_due(10.4)
    now[0] = 11.2  # a tick missed: skipped, not bunched
    core.fire_due(now[0])
    assert fired == [11.2] and core.next_deadline() == 11.5
    timer.undeclare()
    assert core.next_deadline() is None
    core.set_time_source(lambda: 99.0, lambda: 42)
    assert core.clock() == 99.0 and core.now_ns() == 42 and core.sim is None


def test_run_once_fires_what_is_due_then_runs_one_callback():
    now = [0.0]
    core = core_on(now)
    ran: list[str] = []
    core.timer(1.0, lambda: ran.append("tick"))
    core.enqueue(ran.append, "one")
    core.enqueue(ran.append, "two")
    now[0] = 1.0
    assert core.run_once() and ran == ["tick", "one"]
    assert core.run_once() and not core.run_once() and ran == ["tick", "one", "two"]


def test_stop_from_another_thread_ends_run_and_the_shutdown_hooks_run_once():
    core = NodeCore("toy", FakeSession(), logging.getLogger("toy"), time.monotonic, int)
    hooks: list[str] = []
    core.on_shutdown(lambda: hooks.append("stopped"))
    threading.Timer(0.05, core.stop).start()
    assert core.run() and core.stop_requested and hooks == ["stopped"]
    core.shutdown()
    assert hooks == ["stopped"]


def test_a_callback_that_raises_ends_run_with_false_after_the_hooks(caplog):
    core = core_on([0.0])
    hooks: list[str] = []
    core.on_shutdown(lambda: hooks.append("stopped"))
    core.enqueue(lambda: 1 / 0)
    assert core.run() is False and hooks == ["stopped"]
    assert "stopping after an error in node code" in caplog.text


def test_a_bad_payload_is_counted_and_logged_first_then_every_100th(caplog):
    core = core_on([0.0])
    for _ in range(100):
        core.reject("k", "garbage")
    assert core.rejections() == {"k": 100}
    assert caplog.text.count("dropped malformed payload") == 2


# -- a node driven from the test's thread (Node.spin_once, Node.spin_until) ---------------------


def test_spin_until_runs_what_the_node_queued_until_the_condition_holds():
    session = FakeSession()
    node = Node(NodeConfig(name="spun", kind="test", connect="fake"), NoParams(), session)
    seen: list[Pose] = []
    node.subscribe("spun/pose", Pose, seen.append)
    session.deliver("spun/pose", encode(Pose(x=3.0, y=0.0, theta=0.0)))
    assert node.spin_until(lambda: seen, timeout=1.0)
    assert seen == [decode(encode(Pose(x=3.0, y=0.0, theta=0.0)), Pose)]
    assert not node.spin_until(lambda: len(seen) > 1, timeout=0.05)  # nothing more came
    assert not node.spin_once()
