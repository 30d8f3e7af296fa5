"""``turtlectl param``: a running node's parameters, as ``ros2 param list / get / dump``.
Each node answers a get on ``turtlectl/params/<name>`` with its parameters as JSON (the
launch file's ``[node.params]`` after validation); this module fetches and shapes them and
prints nothing itself."""

from __future__ import annotations

import json
from typing import Any

import msgspec

from cli.errors import BadInput, Failed
from cli.services import NobodyServes, Raw, call_service
from messages.keys import params_key

#: s a node has to answer
TIMEOUT = 3.0


def fetch(connect: str, node: str) -> dict[str, Any]:
    """The parameters ``node`` runs with.  NobodyServes (exit 3) naming the live nodes if no
    node of that name answers."""
    try:
        answers = list(call_service(connect, params_key(node), b"", TIMEOUT))
    except NobodyServes:
        from cli import topics

        names = sorted(n.name for n in topics.graph(connect).nodes)
        raise NobodyServes(f"no node named {node!r} answers (running: {', '.join(names) or 'none'})") from None
    if not answers or not isinstance(answers[-1], Raw):
        raise Failed(f"{node} sent no parameters")
    try:
        params = msgspec.json.decode(answers[-1].payload)
    except msgspec.DecodeError as exc:
        raise Failed(f"{node} sent unreadable parameters: {exc}") from None
    if not isinstance(params, dict):
        raise Failed(f"{node} sent parameters that are not a table")
    return params


def value(params: dict[str, Any], node: str, name: str) -> Any:
    """The parameter ``name`` (a dotted path reaches into a table: ``gains.lookahead``)."""
    here: Any = params
    for part in name.split("."):
        if not isinstance(here, dict) or part not in here:
            known = ", ".join(names(params))
            raise BadInput(f"{node} has no parameter {name!r} (it has: {known})")
        here = here[part]
    return here


def names(params: dict[str, Any], prefix: str = "") -> list[str]:
    """Every parameter's name, tables' entries dotted (``gains.lookahead``), in the node's order."""
    out = []
    for key, item in params.items():
        if isinstance(item, dict):
            out += names(item, f"{prefix}{key}.")
        else:
            out.append(prefix + key)
    return out


def toml_value(item: Any) -> str:
    """``item`` as a TOML value (tables inline)."""
    if isinstance(item, bool):
        return "true" if item else "false"
    if isinstance(item, (int, float)):
        return repr(item)
    if isinstance(item, str):
        return json.dumps(item)  # a TOML basic string: the same escapes
    if isinstance(item, list):
        return "[" + ", ".join(toml_value(v) for v in item) + "]"
    if isinstance(item, dict):
        return "{ " + ", ".join(f"{k} = {toml_value(v)}" for k, v in item.items()) + " }" if item else "{}"
    raise BadInput(f"cannot write {item!r} as TOML")


def dump(node: str, params: dict[str, Any]) -> str:
    """``params`` as the body of a launch file's ``[node.params]`` table for ``node``."""
    lines = [f"# {node}: the body of its [node.params] table in a launch file"]
    lines += [f"{key} = {toml_value(item)}" for key, item in params.items()]
    return "\n".join(lines)
