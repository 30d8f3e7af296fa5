"""runtime.params: one parameter changed at run time, validated as the node's config is."""

from __future__ import annotations

from typing import Annotated

import msgspec
import pytest

from turtlectl.nodes.params import NavigatorParams, ObstacleDetectorParams, StatusMonitorParams
from turtlectl.runtime.params import ParamRefused, with_value
from turtlectl.sim.params import SimParams


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
        (NavigatorParams(), "goal_timeout", -1, "goal_timeout must be >= 0.1 (got -1)"),
        (NavigatorParams(), "goal_timeout", "soon", 'goal_timeout must be a number (got "soon")'),
        (ObstacleDetectorParams(), "angle_max", -190, "angle_max must be above angle_min"),
        (SimParams(), "x", 2, "x cannot change at run time: the spawn pose is read once, at start"),
        (StatusMonitorParams(), "battery", 50, "battery cannot change at run time: it is the charge at start"),
        (ObstacleDetectorParams(), "phantom_seed", 3, "phantom_seed cannot change at run time"),
    ],
)
def test_a_change_that_cannot_be_made_says_why(params, name, value, message):
    with pytest.raises(ParamRefused, match=message.replace("(", r"\(").replace(")", r"\)").replace("`", "`")):
        with_value(params, name, value)


def test_describe_gives_every_parameter_with_its_value_now_and_why_it_cannot_change():
    """What every node serves on turtlectl/params/<node>/describe, whatever its kind."""
    from turtlectl.runtime.params import describe

    params, _ = with_value(StatusMonitorParams(), "rate", 2)
    described = describe("status_monitor", "status_monitor", params)
    infos = {p.name: p for p in described.parameters}
    assert (described.node, described.kind) == ("status_monitor", "status_monitor")
    assert [p.name for p in described.parameters] == ["rate", "battery", "drain_per_second", "drain_per_metre"]
    rate = infos["rate"]
    assert (rate.value, rate.unit, rate.range, rate.default, rate.run_time) == (2.0, "Hz", "0.1 to 100", "10", True)
    assert not infos["battery"].run_time and "charge at start" in infos["battery"].fixed_because
    lookahead = {p.name: p for p in describe("navigator", "navigator", NavigatorParams()).parameters}["gains.lookahead"]
    assert lookahead.value == 0.5 and lookahead.unit == "m"


def test_describe_works_for_a_kind_defined_without_source():
    """A node kind written in `python -c` has no source to read its comments from: it is
    described all the same (before: inspect raised on the Zenoh thread)."""
    import msgspec

    from turtlectl.runtime.params import describe

    namespace: dict = {"msgspec": msgspec}
    exec("class Loose(msgspec.Struct):\n    speed: float = 1.0  # m/s: how fast\n", namespace)  # noqa: S102
    info = describe("loose", "loose", namespace["Loose"]()).parameters[0]
    assert (info.name, info.type, info.unit, info.meaning, info.value, info.run_time) == (
        "speed",
        "float",
        "-",
        "",
        1.0,
        True,
    )


class _Point(msgspec.Struct):
    x: float
    y: float


class _Mine(msgspec.Struct):
    """A user's own node kind's parameters."""

    rate: Annotated[float, msgspec.Meta(gt=0, le=50)] = 10.0
    count: Annotated[int, msgspec.Meta(ge=1)] = 3
    names: Annotated[list[str], msgspec.Meta(max_length=2)] = msgspec.field(default_factory=list)
    points: list[_Point] = msgspec.field(default_factory=list)


@pytest.mark.parametrize(
    ("name", "value", "message"),
    [
        ("rate", 60, "rate must be <= 50 (got 60)"),
        ("rate", 0, "rate must be > 0 (got 0)"),
        ("rate", True, "rate must be a number (got true)"),
        ("count", 1.5, "count must be a whole number (got 1.5)"),
        ("names", ["a", "b", "c"], 'names must have at most 2 items (got ["a","b","c"])'),
        ("points", [{"x": 1, "y": 2}, {"x": "far", "y": 2}], "points[1].x must be a number"),
    ],
)
def test_a_value_refused_says_what_it_must_be_in_one_line_without_msgspec_s_path(name, value, message):
    """A user node's refusal reads as a built-in's, not as msgspec's "rate: Expected `float` <= 50.0 - at `$.rate`"."""
    with pytest.raises(ParamRefused) as refused:
        with_value(_Mine(), name, value)
    assert str(refused.value) == message
