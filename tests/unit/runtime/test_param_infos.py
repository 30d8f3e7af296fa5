"""runtime.params.param_infos: what `turtlectl param describe` shows, for every parameter of every node kind."""

from __future__ import annotations

from typing import Annotated

import msgspec

from turtlectl.nodes.kinds import KINDS
from turtlectl.runtime.params import param_infos


def test_every_parameter_of_every_kind_has_a_unit_a_meaning_and_a_range():
    for kind, spec in KINDS.items():
        for info in param_infos(spec.params):
            assert info.unit and info.unit != "-" or info.name == "phantom_seed", (kind, info)
            assert info.meaning and info.range and info.default, (kind, info)
            assert info.run_time == (info.fixed_because == ""), (kind, info)


def test_describe_reads_constraints_defaults_and_what_is_fixed():
    nav = {i.name: i for i in param_infos(KINDS["navigator"].params)}
    assert (nav["goal_timeout"].unit, nav["goal_timeout"].range, nav["goal_timeout"].default) == (
        "s",
        "0.1 to 3600",
        "30",
    )
    assert nav["robot_radius"].range == "> 0" and nav["clearance"].range == ">= 0"
    assert nav["gains.lookahead"].unit == "m" and nav["gains.lookahead"].run_time
    sim = {i.name: i for i in param_infos(KINDS["sim"].params)}
    assert not sim["x"].run_time and "teleport" in sim["x"].fixed_because and sim["cmd_timeout"].run_time
    detector = {i.name: i for i in param_infos(KINDS["obstacle_detector"].params)}
    assert detector["undeclared_obstacles"].range == "at most 100 items" and detector["beams"].type == "int"


def test_an_exclusive_bound_reads_as_exclusive_beside_the_other_one():
    """A user node's ``Annotated[float, Meta(gt=0, le=50)]`` read "0 to 50", as if 0 were allowed."""
    ranges = {info.name: info.range for info in param_infos(_Bounded)}
    assert ranges == {
        "rate": "> 0 and <= 50",
        "share": ">= 0 and < 1",
        "gap": "> -1 and < 1",
        "span": "0.1 to 100",
        "floor": "> 0",
        "ceiling": "< 5",
    }


class _Bounded(msgspec.Struct):
    rate: Annotated[float, msgspec.Meta(gt=0, le=50)] = 10.0
    share: Annotated[float, msgspec.Meta(ge=0, lt=1)] = 0.5
    gap: Annotated[float, msgspec.Meta(gt=-1, lt=1)] = 0.0
    span: Annotated[float, msgspec.Meta(ge=0.1, le=100)] = 1.0
    floor: Annotated[float, msgspec.Meta(gt=0)] = 1.0
    ceiling: Annotated[int, msgspec.Meta(lt=5)] = 1
