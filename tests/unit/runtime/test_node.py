"""runtime.node: timers keep an absolute grid, paused or not."""

import pytest

from turtlectl.runtime.node import Timer


def test_timer_keeps_an_absolute_grid_and_skips_missed_ticks():
    t = Timer(0.1, lambda: None, start=100.0)
    assert t.deadline == pytest.approx(100.1)
    t.advance(100.1003)  # on time, callback took 0.3 ms
    assert t.deadline == pytest.approx(100.2)
    t.advance(100.4501)  # a 250 ms stall: next tick back on the grid, not bunched
    assert t.deadline == pytest.approx(100.5)


def test_a_resumed_timer_ticks_on_its_grid():
    t = Timer(0.1, lambda: None, start=100.0)
    t.pause()
    assert not t.active
    t.resume(100.05)  # paused and resumed within a period: the pending tick stays
    assert t.active and t.deadline == pytest.approx(100.1)
    t.pause()
    t.resume(100.73)  # paused across ticks: the next one on the grid after now
    assert t.deadline == pytest.approx(100.8)
    t.advance(100.8001)
    assert t.deadline == pytest.approx(100.9)


def test_a_retimed_timer_ticks_a_new_period_from_now():
    """`param set status_monitor rate 2` takes effect at once."""
    t = Timer(0.1, lambda: None, start=100.0)
    t.retime(0.5, now=100.23)
    assert t.period == 0.5 and t.deadline == pytest.approx(100.73)
    t.advance(100.73)
    assert t.deadline == pytest.approx(101.23)
