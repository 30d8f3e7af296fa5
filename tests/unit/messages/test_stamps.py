"""messages.stamps: the one stamping of a message as it is sent (node publishers, ``pub``, ``Client.publish``)."""

from __future__ import annotations

from turtlectl.messages import Message, Pose, Twist
from turtlectl.messages.stamps import with_stamp


class Plain(Message, tag="test_stamps/Plain"):
    value: float = 0.0


class StampOnly(Message, tag="test_stamps/StampOnly"):
    stamp: int = 0


def test_a_type_with_stamp_and_seq_gets_both():
    assert with_stamp(Twist(linear=1.0), lambda: 42, 7) == Twist(linear=1.0, stamp=42, seq=7)
    assert with_stamp(Pose(x=1.0, y=2.0, theta=0.0), lambda: 5, 0) == Pose(x=1.0, y=2.0, theta=0.0, stamp=5, seq=0)


def test_a_type_without_both_is_sent_as_it_is_and_the_clock_is_not_read():
    def clock() -> int:
        raise AssertionError("read")

    plain, stamp_only = Plain(value=1.0), StampOnly(stamp=3)
    assert with_stamp(plain, clock, 1) is plain
    assert with_stamp(stamp_only, clock, 1) is stamp_only
