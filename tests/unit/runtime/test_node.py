"""runtime.node: timers keep an absolute grid."""

import pytest

from runtime.node import _Timer


def test_timer_keeps_an_absolute_grid_and_skips_missed_ticks():
    t = _Timer(0.1, lambda: None, start=100.0)
    assert t.deadline == pytest.approx(100.1)
    t.advance(100.1003)  # on time, callback took 0.3 ms
    assert t.deadline == pytest.approx(100.2)
    t.advance(100.4501)  # a 250 ms stall: next tick back on the grid, not bunched
    assert t.deadline == pytest.approx(100.5)
