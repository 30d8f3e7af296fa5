"""Changing a running node's parameters (pure: no zenoh): the dotted name, what may change
while the node runs, and the new parameters validated as the node's config is.

A parameter Struct lists what cannot change at run time, and why, in a class variable
``FIXED`` (``{"x": "the spawn pose is read once, at start"}``); everything else can, and
the node applies it at once (its ``Node.on_params`` hooks).  ``describe`` is what every node
serves about its parameters, read from its Struct, whatever its kind."""

from __future__ import annotations

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
        raise ParamRefused(f"{name}: {exc}") from None
    return new, old


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
