"""Simulated time (runtime.simtime): a node started with ``use_sim_time`` runs its timers, its
``clock()`` and the stamps of what it publishes on the simulator's ``clock`` key; the simulator,
which makes the time, keeps the machine's clock for its own pace.  On the in-memory session of
runtime.fake (no Zenoh, no wall clock)."""

from __future__ import annotations

import msgspec
import pytest

from turtlectl.messages import Clock, Twist, decode, encode
from turtlectl.messages.keys import CLOCK
from turtlectl.runtime.config import NodeConfig
from turtlectl.runtime.fake import FakeSession
from turtlectl.runtime.node import Node
from turtlectl.runtime.simtime import SimClock


class NoParams(msgspec.Struct):
    pass


def sim_node(use_sim_time: bool = True) -> tuple[Node[NoParams], FakeSession]:
    session = FakeSession()
    config = NodeConfig(name="follower", kind="Follower", connect="fake", use_sim_time=use_sim_time)
    return Node(config, NoParams(), session, clock=lambda: 1234.0), session  # type: ignore[arg-type]


def tick(session: FakeSession, ns: int) -> None:
    session.deliver(CLOCK, encode(Clock(clock=ns, real_time_factor=5.0)))


def stamps(session: FakeSession, key: str) -> list[int]:
    return [decode(data, Twist).stamp for k, data in session.published if k == key]


def test_the_time_is_zero_until_the_first_clock_then_the_clocks():
    node, session = sim_node()
    assert node.uses_sim_time and node.clock() == 0.0 and node.now_ns() == 0
    pub = node.publisher("out", Twist)
    pub.publish(Twist())
    tick(session, 5_000_000_000)
    assert node.clock() == 0.0  # until the node's thread takes the new time (its timers with it)
    node.core.drain()
    assert node.clock() == 5.0 and node.now_ns() == 5_000_000_000
    pub.publish(Twist())
    assert stamps(session, "out") == [0, 5_000_000_000]  # stamped with the simulated time
    tick(session, 4_000_000_000)  # a late or repeated clock never takes the time back
    assert node.clock() == 5.0


def test_without_use_sim_time_the_machines_clock_and_no_clock_subscription():
    node, session = sim_node(use_sim_time=False)
    assert node.clock() == 1234.0 and not node.uses_sim_time
    assert CLOCK not in [s.key for s in session.subscribers]
    tick(session, 5_000_000_000)
    assert node.clock() == 1234.0


def test_timers_run_on_the_simulated_time_and_a_clock_past_the_next_deadline_wakes_the_node():
    node, session = sim_node()
    tick(session, 10_000_000_000)
    node.core.drain()
    fired: list[float] = []
    node.timer(0.1, lambda: fired.append(node.clock()))
    node.core.sim.wake_at = node.core.next_deadline()  # as the node's loop sets it before it waits
    tick(session, 10_050_000_000)
    assert node.core.pending() == 0  # not due: the thread sleeps on
    node.core.fire_due(node.clock())
    assert fired == []
    tick(session, 10_100_000_000)
    assert node.core.pending()  # due: the thread is woken
    node.core.drain()
    node.core.fire_due(node.clock())
    assert fired == [pytest.approx(10.1, abs=0.016)]  # at most a step on, as the time runs between Clocks


def test_a_malformed_clock_is_counted_and_logged_and_the_time_holds(caplog):
    node, session = sim_node()
    tick(session, 7_000_000_000)
    node.core.drain()
    session.deliver(CLOCK, b"garbage")
    node.core.drain()
    assert node.core.rejections() == {CLOCK: 1}
    assert "dropped malformed payload #1 on clock" in caplog.text
    assert node.clock() == 7.0


def test_a_node_that_makes_the_time_stamps_with_it_and_keeps_the_machines_clock():
    node, session = sim_node()
    made = [3_000_000_000]
    node.use_time(lambda: made[0])
    assert node.clock() == 1234.0  # its timers pace it: the machine's clock
    assert CLOCK not in [s.key for s in session.subscribers]  # it does not follow a clock
    node.publisher("pose", Twist).publish(Twist())
    assert stamps(session, "pose") == [3_000_000_000]


def test_between_two_clocks_the_time_runs_on_at_their_factor_by_at_most_a_step():
    wall = [100.0]
    woken: list[int] = []
    sim = SimClock(lambda: woken.append(1), lambda why: None, monotonic=lambda: wall[0])
    assert sim.now() == 0.0 and sim.timeout(5.0) == 1.0  # no time yet: a Clock wakes the node
    sim.heard(encode(Clock(clock=10_000_000_000, real_time_factor=5.0)))
    sim.heard(encode(Clock(clock=10_016_000_000, real_time_factor=5.0)))  # a step of 16 ms
    assert sim.now() == 10.016
    wall[0] += 0.002  # 2 ms of wall clock: 10 ms of simulated time at 5x
    assert sim.now_ns() == 10_026_000_000
    assert sim.timeout(10.030) == pytest.approx(0.004 / 5.0)  # the deadline comes 4 simulated ms on
    wall[0] += 0.010  # the simulator stalls: the time stops a step after its last Clock
    assert sim.now_ns() == 10_032_000_000 and sim.timeout(10.040) == 1.0  # the next Clock wakes it
    sim.wake_at = 10.040
    sim.heard(encode(Clock(clock=10_048_000_000, real_time_factor=5.0)))
    assert woken == [1] and sim.now() == 10.048
    sim.heard(encode(Clock(clock=10_020_000_000, real_time_factor=5.0)))  # from the past: ignored
    assert sim.now() == 10.048


def test_timers_made_before_the_first_clock_tick_a_period_after_it_not_on_a_grid_from_0():
    """A 1 s timer's grid starts at the first Clock, not at time 0 (it would fire at once, then
    on whole seconds since 1970)."""
    node, session = sim_node()
    fired: list[float] = []
    node.timer(1.0, lambda: fired.append(node.clock()))
    tick(session, 1_795_659_174_987_000_000)
    node.core.drain()
    node.core.fire_due(node.clock())
    assert fired == []
    assert node.core.next_deadline() == pytest.approx(1_795_659_175.987)


def test_a_jump_back_starts_the_timers_again_from_the_new_time(caplog):
    """``play --loop --clock``: the recording's time starts again, and so do the
    timers (they would stop for good if the node's time could not go back)."""
    node, session = sim_node()
    tick(session, 100_000_000_000)
    node.core.drain()
    node.timer(0.5, lambda: None)
    tick(session, 100_400_000_000)
    tick(session, 100_300_000_000)  # a late one: ignored
    node.core.drain()
    assert node.clock() == pytest.approx(100.4, abs=0.02)
    tick(session, 96_000_000_000)  # 4.4 s back: the replay looped
    node.core.drain()
    assert node.clock() == pytest.approx(96.0, abs=0.02)
    assert node.core.next_deadline() == pytest.approx(96.5, abs=0.02)
    assert "the clock went back 4.400 s" in caplog.text


def test_a_node_with_no_clock_says_so_once(monkeypatch, caplog):
    """A use_sim_time node beside no simulator says so, rather than stay silent forever."""
    import threading

    import turtlectl.runtime.simtime as simtime

    monkeypatch.setattr(simtime, "WAIT_FOR_CLOCK", 0.05)
    node, _ = sim_node()
    spinning = threading.Thread(target=node.spin)
    spinning.start()
    try:
        deadline = threading.Event()
        for _ in range(100):  # up to 5 s for the warning, under a deadline
            if "no clock yet (use_sim_time)" in caplog.text:
                break
            deadline.wait(0.05)
    finally:
        node.stop()
        spinning.join(5)
    assert caplog.text.count("no clock yet (use_sim_time): its timers wait for a simulator to publish clock") == 1
