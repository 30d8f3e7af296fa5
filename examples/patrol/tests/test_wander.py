"""The wanderer: its pure rule (``command``), the node on a fake clock, and in the real system."""

from __future__ import annotations

import math

import pytest
from test_system import poses_until
from wander import Wanderer, WanderParams, command

from turtlectl.messages import LaserScan, Twist
from turtlectl.testing import FakeNode, unstamped


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
    # what it published carries its stamp and seq: unstamped() compares it with a Twist built here
    assert [unstamped(t) for t in fake.published("turtle1/cmd_vel")] == [Twist(linear=0.8)] * 3
    fake.deliver("obstacles", scan(0.2))
    fake.advance(0.1)
    assert unstamped(fake.published("turtle1/cmd_vel")[-1]) == Twist(linear=0.0, angular=1.5)
    fake.shutdown()
    assert unstamped(fake.published("turtle1/cmd_vel")[-1]) == Twist(linear=0.0, angular=0.0)


@pytest.mark.turtlectl_launch("../wander.toml", "--set", "wanderer.speed=1.0")
def test_the_wanderer_drives_and_turns_before_the_obstacle(turtlectl_system):
    client = turtlectl_system
    assert client.param("wanderer", "speed") == 1.0
    poses_until(client, lambda p: p.linear_velocity > 0.5, seconds=20.0)  # driving towards it
    turned = poses_until(client, lambda p: p.angular_velocity > 0.5, seconds=20.0)  # and turning away
    assert turned.x < 8.5 - 0.8, turned  # before it reached the obstacle
