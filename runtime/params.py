"""A node's parameters (pure: no zenoh): what each one is, read from the node's parameter
Struct itself, and changing them while the node runs.

Described (``param_infos``, ``describe``): each parameter's type, unit, range, default,
meaning and whether it can change while the node runs, so that a node kind nobody else
knows is described as well as the built-in ones; every node serves that as a
``messages.params.ParamDescription``.  A parameter Struct keeps each field's
``# unit: meaning`` as a comment after it, and lists what cannot change at run time, and
why, in a class variable ``FIXED`` (``{"x": "the spawn pose is read once, at start"}``).

Changed (``with_value``): the dotted name, what may change while the node runs, and the new
parameters validated as the node's config is; the node applies them at once (its
``Node.on_params`` hooks)."""

from __future__ import annotations

import re
from typing import Any

import msgspec

from turtlectl.messages.described import field_comments as field_comments  # also for the nodes' Params
from turtlectl.messages.fieldtext import default_text, doc, struct_fields, type_name
from turtlectl.messages.params import ParamDescription, ParamInfo
from turtlectl.runtime.client.errors import BadInput

BIG = 1e9  # the stand-in for "finite" (messages.units)


# -- described -----------------------------------------------------------
def fixed_reason(params_type: type, name: str) -> str | None:
    """Why parameter ``name`` (dotted) of ``params_type`` cannot change while its node runs,
    or None: a parameter Struct lists those in its class variable ``FIXED``."""
    fixed: dict[str, str] = getattr(params_type, "FIXED", {})
    return fixed.get(name, fixed.get(name.split(".", 1)[0]))


def range_text(t: msgspec.inspect.Type) -> str:
    """The values a constrained type takes: ``0.1 to 100`` (both ends allowed), ``> 0``,
    ``> 0 and <= 50`` (an end not allowed is written as such), ``at most 100 items``."""
    bounds = [(op, getattr(t, key, None)) for key, op in (("ge", ">="), ("gt", ">"), ("le", "<="), ("lt", "<"))]
    lo = next((f"{op} {v:g}" for op, v in bounds[:2] if v is not None and v > -BIG), None)
    hi = next((f"{op} {v:g}" for op, v in bounds[2:] if v is not None and v < BIG), None)
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


# -- changed --------------------------------------------------------------
class ParamRefused(BadInput, ValueError):
    """The change is not possible: unknown parameter, fixed at run time, or an invalid value (exit code 2)."""


def lookup(table: dict[str, Any], name: str) -> Any:
    """The value at dotted ``name`` in ``table``; KeyError if there is none."""
    here: Any = table
    for part in name.split("."):
        if not isinstance(here, dict) or part not in here:
            raise KeyError(name)
        here = here[part]
    return here


def with_value(params: msgspec.Struct, name: str, value: Any) -> tuple[msgspec.Struct, Any]:
    """``params`` with the dotted parameter ``name`` set to ``value``, validated as the node's
    config is (strict), and the value it had.  ParamRefused says why not."""
    table = msgspec.to_builtins(params)
    try:
        old = lookup(table, name)
    except KeyError:
        raise ParamRefused(f"no parameter {name!r}") from None
    if isinstance(old, dict):
        raise ParamRefused(f"{name} is a table: set one of its entries ({name}.KEY)")
    reason = fixed_reason(type(params), name)
    if reason is not None:
        raise ParamRefused(f"{name} cannot change at run time: {reason}")
    *path, last = name.split(".")
    here = table
    for part in path:
        here = here[part]
    here[last] = value
    try:
        new = msgspec.convert(table, type(params), strict=True)
    except msgspec.ValidationError as exc:
        raise ParamRefused(refusal(name, value, str(exc))) from None
    return new, old


_AT = re.compile(r"^(?P<what>.*?)(?: - at `\$(?P<path>[^`]*)`)?$", re.S)
_BOUND = re.compile(r"^Expected `\w+` (?P<op>[<>]=?) (?P<bound>\S+)$")
_TYPE = re.compile(r"^Expected `(?P<type>[^`]+)`, got `[^`]+`$")
_LENGTH = re.compile(r"^Expected `(?P<type>\w+)` of length (?P<op>[<>]=?) (?P<count>\d+)$")
_KINDS = {"float": "a number", "int": "a whole number", "str": "text", "bool": "true or false"}
_KINDS |= {"array": "a list", "object": "a table", "null": "null"}


def validation_parts(error: msgspec.ValidationError | str) -> tuple[str, str]:
    """msgspec's message split into what is wrong and where (``.a.b[0]``, empty at the top)."""
    text = str(error)
    match = _AT.match(text)
    return (match["what"], match["path"] or "") if match else (text, "")


def refusal(name: str, value: Any, error: str) -> str:
    """msgspec's ``error`` for parameter ``name`` set to ``value``, as one line a user reads,
    the same for every node kind: ``rate must be <= 50 (got 60)``, ``count must be a whole
    number (got 1.5)``; a problem inside the value (an item of a list) is named by its place,
    ``points[1].x must be a number``; anything else keeps msgspec's own words."""
    what, path = validation_parts(error)
    path = path.removeprefix(".")
    where = path if path.startswith(name) else name
    words = in_words(what)
    return (
        f"{where} {words}{got(value)}"
        if words and where == name
        else f"{where} {words}"
        if words
        else f"{where}: {what}"
    )


def got(value: Any) -> str:
    """`` (got "fast")``: the value a user gave, as JSON, after what is wrong with it."""
    return f" (got {msgspec.json.encode(value).decode()})"


def in_words(what: str) -> str | None:
    """msgspec's complaint about one value (without its place) in a user's words, the one
    wording of parameters set at run time and of launch files: ``must be a number``, ``must be
    <= 50``, ``must have at most 3 items``; None when it is none of those."""
    if bound := _BOUND.match(what):
        limit = float(bound["bound"])
        return "must be a finite number" if abs(limit) >= BIG else f"must be {bound['op']} {limit:g}"
    if length := _LENGTH.match(what):
        most = "at most" if length["op"].startswith("<") else "at least"
        items = "characters" if length["type"] == "str" else "items"
        return f"must have {most} {length['count']} {items}"
    if kind := _TYPE.match(what):
        return f"must be {_KINDS.get(kind['type'], kind['type'])}"
    return None


def describe(node: str, kind: str, params: msgspec.Struct, infos: list[ParamInfo] | None = None) -> ParamDescription:
    """What node ``node`` of ``kind`` serves about its parameters: each one's description
    (``infos``, made from ``params``' Struct when not given) with its value in ``params``."""
    table = msgspec.to_builtins(params)
    described = []
    for info in param_infos(type(params)) if infos is None else infos:
        try:
            now = lookup(table, info.name)
        except KeyError:
            now = None
        described.append(msgspec.structs.replace(info, value=now))
    return ParamDescription(node=node, kind=kind, doc=doc(type(params)), parameters=described)
