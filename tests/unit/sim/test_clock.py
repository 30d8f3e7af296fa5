"""The simulator makes the time (runtime.simtime): a ``Clock`` on ``clock`` after every step,
16 ms of simulated time per step, the steps ``real_time_factor`` times as often as at 1; its
poses stamped with the simulated time when the system runs on it.  On runtime.fake's clock."""

from __future__ import annotations

import pytest

from turtlectl.messages import Clock, Pose, Twist, decode, encode
from turtlectl.messages.keys import CLOCK, CMD_VEL, POSE
from turtlectl.runtime.fake import FakeNode
from turtlectl.sim.kinematics import STEP
from turtlectl.sim.node import Simulator
from turtlectl.sim.params import SimParams


def published(fake: FakeNode, key: str, kind: type) -> list:
    return [decode(data, kind) for k, data in fake.session.published if k == key]


@pytest.mark.parametrize("factor", [1.0, 5.0, 0.5])
def test_a_clock_after_every_step_16_ms_of_simulated_time_each_at_the_factors_pace(factor):
    fake = FakeNode(Simulator, SimParams(real_time_factor=factor), name="sim")
    fake.advance(10 * STEP / factor + 1e-9)  # wall time for ten steps at this factor
    clocks = published(fake, CLOCK, Clock)
    assert len(clocks) == 10
    assert {b.clock - a.clock for a, b in zip(clocks, clocks[1:], strict=False)} == {16_000_000}
    assert {c.real_time_factor for c in clocks} == {factor}


def test_poses_carry_the_simulated_time_when_the_factor_is_not_1_and_the_wall_clock_at_1():
    fast = FakeNode(Simulator, SimParams(real_time_factor=5.0), name="sim")
    fast.advance(3 * STEP / 5.0 + 1e-9)
    clocks, poses = published(fast, CLOCK, Clock), published(fast, POSE, Pose)
    assert [p.stamp for p in poses] == [c.clock for c in clocks]
    real = FakeNode(Simulator, SimParams(), name="sim")
    real.advance(3 * STEP + 1e-9)
    assert [p.stamp for p in published(real, POSE, Pose)] != [c.clock for c in published(real, CLOCK, Clock)]


def test_cmd_timeout_is_simulated_time():
    """At 5x the turtle stops 1 simulated second after its last command: 0.2 s of wall time."""
    fake = FakeNode(Simulator, SimParams(real_time_factor=5.0, cmd_timeout=1.0), name="sim")
    fake.advance(STEP)
    fake.session.deliver(CMD_VEL, encode(Twist(linear=1.0)))
    fake.advance(0.1)  # 0.5 simulated s: still driving
    assert published(fake, POSE, Pose)[-1].linear_velocity > 0.9
    fake.advance(0.15)  # 1.25 simulated s: stopped (braking at the limits takes 0.1 s)
    assert published(fake, POSE, Pose)[-1].linear_velocity == 0.0


def test_the_factor_changes_at_run_time():
    fake = FakeNode(Simulator, SimParams(), name="sim")
    fake.set_param("real_time_factor", 4.0)
    before = len(published(fake, CLOCK, Clock))
    fake.advance(10 * STEP / 4.0 + 1e-9)
    assert len(published(fake, CLOCK, Clock)) - before == 10
