"""What a node serves about its parameters, on the wire: every node answers a get on
``turtlectl/params/<node>/describe`` with a ``ParamDescription`` (JSON), one ``ParamInfo``
for each parameter (type, unit, range, default, meaning, whether it can change while the
node runs, its value now); ``turtlectl param`` works from that answer alone.

The Structs only: the description is read from the node's parameter Struct by
runtime.params (``param_infos``), where parameters live."""

from __future__ import annotations

from typing import Any

import msgspec


class ParamInfo(msgspec.Struct, kw_only=True):
    """One parameter of a node, as ``turtlectl param describe`` shows it."""

    name: str  # dotted into tables (gains.lookahead)
    type: str  # float, int, bool, str, list[...], map, any
    unit: str  # "-" when it has none
    range: str  # the values it takes: "0.1 to 100" (both ends allowed), "> 0", "> 0 and <= 50", "any"
    default: str  # its default, as text ("required" if it has none)
    meaning: str  # what it does (from the field's comment; "" if it has none)
    run_time: bool  # can change while the node runs (`turtlectl param set`)
    fixed_because: str = ""  # why not, when it cannot ("" when it can)
    value: Any = None  # its value now, as the node runs with it


class ParamDescription(msgspec.Struct, kw_only=True):
    """A node's answer on ``turtlectl/params/<node>/describe`` (JSON): every parameter it runs
    with, tables' entries dotted, in the node's order, each with its value now."""

    node: str  # the node's name
    kind: str  # its kind (the launch file's `run`; a user's own kind too)
    doc: str  # the parameter Struct's docstring
    parameters: list[ParamInfo]  # one per parameter, tables' entries dotted, in the node's order
