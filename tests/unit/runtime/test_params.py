"""runtime.params: one parameter changed at run time, validated as the node's config is."""

from __future__ import annotations

import pytest

from nodes.params import NavigatorParams, ObstacleDetectorParams, StatusMonitorParams
from runtime.params import ParamRefused, with_value
from sim.params import SimParams


def test_a_value_is_set_converted_and_the_old_one_returned():
    new, old = with_value(NavigatorParams(), "goal_timeout", 60)
    assert (new.goal_timeout, old) == (60.0, 30.0) and isinstance(new.goal_timeout, float)
    new, old = with_value(NavigatorParams(), "gains.lookahead", 0.7)
    assert (new.gains.lookahead, old) == (0.7, 0.5) and new.goal_timeout == 30.0


@pytest.mark.parametrize(
    ("params", "name", "value", "message"),
    [
        (NavigatorParams(), "goal_timeot", 1, "no parameter 'goal_timeot'"),
        (NavigatorParams(), "gains", 1, "gains is a table: set one of its entries (gains.KEY)"),
        (NavigatorParams(), "goal_timeout", -1, "goal_timeout: Expected `float` >= 0.1"),
        (NavigatorParams(), "goal_timeout", "soon", "goal_timeout: Expected `float`, got `str`"),
        (ObstacleDetectorParams(), "angle_max", -190, "angle_max must be above angle_min"),
        (SimParams(), "x", 2, "x cannot change at run time: the spawn pose is read once, at start"),
        (StatusMonitorParams(), "battery", 50, "battery cannot change at run time: it is the charge at start"),
        (ObstacleDetectorParams(), "phantom_seed", 3, "phantom_seed cannot change at run time"),
    ],
)
def test_a_change_that_cannot_be_made_says_why(params, name, value, message):
    with pytest.raises(ParamRefused, match=message.replace("(", r"\(").replace(")", r"\)").replace("`", "`")):
        with_value(params, name, value)
