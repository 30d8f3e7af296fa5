"""What a node serves about its parameters (pure: no zenoh): each one's type, unit, range,
default, meaning and whether it can change while the node runs, read from the node's
parameter Struct itself, so that a node kind nobody else knows is described as well as the
built-in ones.  Every node answers a get on ``turtlectl/params/<node>/describe`` with a
``ParamDescription`` (JSON); ``turtlectl param`` works from that answer alone.

A parameter Struct keeps each field's ``# unit: meaning`` as a comment after it, and lists
what cannot change at run time, and why, in a class variable ``FIXED``."""

from __future__ import annotations

import inspect
from typing import Any

import msgspec

from messages.reference import default_text, struct_fields, type_name


def field_comments(cls: type) -> dict[str, str]:
    """``# comments`` after the fields in the class's source: parameter Structs keep each
    field's ``unit: meaning`` there.  A class without source (defined in ``python -c``, or
    shipped without its .py) has none: its parameters are described without them."""
    try:
        source = inspect.getsource(cls)
    except (OSError, TypeError):
        return {}
    found: dict[str, str] = {}
    for line in source.splitlines():
        name, colon, rest = line.strip().partition(":")
        if colon and name.isidentifier() and "#" in rest:
            found[name] = rest.split("#", 1)[1].strip()
    return found


def fixed_reason(params_type: type, name: str) -> str | None:
    """Why parameter ``name`` (dotted) of ``params_type`` cannot change while its node runs,
    or None: a parameter Struct lists those in its class variable ``FIXED``."""
    fixed: dict[str, str] = getattr(params_type, "FIXED", {})
    return fixed.get(name, fixed.get(name.split(".", 1)[0]))


def range_text(t: msgspec.inspect.Type) -> str:
    """The values a constrained type takes: ``0.1 to 100`` (both ends allowed), ``> 0``,
    ``> 0 and <= 50`` (an end not allowed is written as such), ``at most 100 items``."""
    big = 1e9  # the stand-in for "finite" (messages.units)
    bounds = [(op, getattr(t, key, None)) for key, op in (("ge", ">="), ("gt", ">"), ("le", "<="), ("lt", "<"))]
    lo = next((f"{op} {v:g}" for op, v in bounds[:2] if v is not None and v > -big), None)
    hi = next((f"{op} {v:g}" for op, v in bounds[2:] if v is not None and v < big), None)
    if lo is not None and hi is not None:
        if lo.startswith(">=") and hi.startswith("<="):
            return f"{lo[3:]} to {hi[3:]}"
        return f"{lo} and {hi}"
    if lo is not None or hi is not None:
        return lo or hi or ""
    if isinstance(t, msgspec.inspect.ListType) and t.max_length is not None:
        return f"at most {t.max_length} items"
    if isinstance(t, msgspec.inspect.FloatType):
        return "any finite number" if bounds[0][1] is not None else "any number"
    return "any"


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


def param_infos(params_type: type, prefix: str = "", root: type | None = None) -> list[ParamInfo]:
    """Every parameter of ``params_type``, tables' entries dotted (``gains.lookahead``): type,
    unit and meaning (its ``# unit: meaning`` comment), range, default, and whether it can
    change at run time."""
    root = root or params_type
    comments = field_comments(params_type)
    out: list[ParamInfo] = []
    for f in struct_fields(params_type):
        if isinstance(f.type, msgspec.inspect.StructType):
            out += param_infos(f.type.cls, f"{prefix}{f.name}.", root)
            continue
        unit, _, meaning = comments.get(f.name, "-: ").partition(": ")
        name = prefix + f.name
        reason = fixed_reason(root, name)
        out.append(
            ParamInfo(
                name=name,
                type=type_name(f.type),
                unit=unit,
                range=range_text(f.type),
                default=default_text(f),
                meaning=meaning,
                run_time=reason is None,
                fixed_because=reason or "",
            )
        )
    return out
