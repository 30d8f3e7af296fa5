"""The wanderer, unit-tested: its pure rule (``command``) and the node on a fake clock."""

from __future__ import annotations

import math

from wander import Wanderer, WanderParams, command

from turtlectl.messages import LaserScan, Twist
from turtlectl.testing import FakeNode


def scan(ahead: float) -> LaserScan:
    """Three beams, -30, 0 and +30 degrees; something ``ahead`` m away straight on."""
    step = math.radians(30)
    return LaserScan(
        angle_min=-step,
        angle_max=step,
        angle_increment=step,
        range_min=0.0,
        range_max=10.0,
        ranges=[math.inf, ahead, math.inf],
    )


def test_forward_when_clear_turn_when_something_is_close_ahead():
    p = WanderParams(speed=1.0, turn=2.0, clearance=0.5)
    assert command(scan(math.inf), p) == Twist(linear=1.0, angular=0.0)
    assert command(scan(0.4), p) == Twist(linear=0.0, angular=2.0)
    assert command(None, p) == Twist(linear=0.0, angular=0.0)


def test_the_node_commands_at_its_rate_from_the_newest_scan_and_stops_at_shutdown():
    fake = FakeNode(Wanderer, {"rate": 10.0, "clearance": 0.5})
    fake.deliver("obstacles", scan(3.0))
    fake.advance(0.3)
    assert [t.linear for t in fake.published("turtle1/cmd_vel")] == [0.8, 0.8, 0.8]
    fake.deliver("obstacles", scan(0.2))
    fake.advance(0.1)
    assert fake.published("turtle1/cmd_vel")[-1].angular == 1.5
    fake.shutdown()
    last = fake.published("turtle1/cmd_vel")[-1]
    assert (last.linear, last.angular) == (0.0, 0.0)
