"""Changing a running node's parameters (pure: no zenoh): the dotted name, what may change
while the node runs, and the new parameters validated as the node's config is.

A parameter Struct lists what cannot change at run time, and why, in a class variable
``FIXED`` (``{"x": "the spawn pose is read once, at start"}``); everything else can, and
the node applies it at once (its ``Node.on_params`` hooks).  ``describe`` is what every node
serves about its parameters, read from its Struct, whatever its kind."""

from __future__ import annotations

import re
from typing import Any

import msgspec

from messages.params import ParamDescription, ParamInfo, fixed_reason, param_infos
from messages.reference import doc


class ParamRefused(ValueError):
    """The change is not possible: unknown parameter, fixed at run time, or an invalid value."""


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


_AT = re.compile(r"^(?P<what>.*?)(?: - at `\$\.?(?P<path>[^`]*)`)?$", re.S)
_BOUND = re.compile(r"^Expected `\w+` (?P<op>[<>]=?) (?P<bound>\S+)$")
_TYPE = re.compile(r"^Expected `(?P<type>[^`]+)`, got `[^`]+`$")
_LENGTH = re.compile(r"^Expected `(?P<type>\w+)` of length (?P<op>[<>]=?) (?P<count>\d+)$")
_KINDS = {"float": "a number", "int": "a whole number", "str": "text", "bool": "true or false"}
_KINDS |= {"array": "a list", "object": "a table", "null": "null"}
BIG = 1e9  # the stand-in for "finite" (messages.units)


def refusal(name: str, value: Any, error: str) -> str:
    """msgspec's ``error`` for parameter ``name`` set to ``value``, as one line a user reads,
    the same for every node kind: ``rate must be <= 50 (got 60)``, ``count must be a whole
    number (got 1.5)``; a problem inside the value (an item of a list) is named by its place,
    ``points[1].x must be a number``; anything else keeps msgspec's own words."""
    match = _AT.match(error)
    what, path = (match["what"], match["path"] or "") if match else (error, "")
    where = path if path.startswith(name) else name
    got = f" (got {msgspec.json.encode(value).decode()})" if where == name else ""
    if bound := _BOUND.match(what):
        limit = float(bound["bound"])
        if abs(limit) >= BIG:
            return f"{where} must be a finite number{got}"
        return f"{where} must be {bound['op']} {limit:g}{got}"
    if length := _LENGTH.match(what):
        most = "at most" if length["op"].startswith("<") else "at least"
        items = "characters" if length["type"] == "str" else "items"
        return f"{where} must have {most} {length['count']} {items}{got}"
    if kind := _TYPE.match(what):
        return f"{where} must be {_KINDS.get(kind['type'], kind['type'])}{got}"
    return f"{where}: {what}"


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
