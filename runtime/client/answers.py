"""What a node answers about itself, read: its parameters (``turtlectl/params/<node>``) and its
details (``turtlectl/nodes/<node>``).  Pure: no session; Failed or BadInput for an answer that
does not read or a parameter it does not have.
"""

from __future__ import annotations

from typing import Any

import msgspec

from turtlectl.messages.keys import NodeDetails
from turtlectl.runtime.client.errors import BadInput, Failed
from turtlectl.runtime.client.services import Raw
from turtlectl.runtime.loader import suggestion
from turtlectl.runtime.params import lookup


def parse_params(node: str, payload: bytes) -> dict[str, Any]:
    """``node``'s answer on ``turtlectl/params/<node>`` as its table of parameters; Failed if it is none."""
    try:
        params = msgspec.json.decode(payload)
    except msgspec.DecodeError as exc:
        raise Failed(f"{node} sent unreadable parameters: {exc}") from None
    if not isinstance(params, dict):
        raise Failed(f"{node} sent parameters that are not a table")
    return params


def no_param(node: str, name: str, known: list[str]) -> BadInput:
    """An unknown parameter: the nearest one suggested, all of them named."""
    return BadInput(f"{node} has no parameter {name!r}{suggestion(name, known)} (it has: {', '.join(known)})")


def value(params: dict[str, Any], node: str, name: str) -> Any:
    """The parameter ``name`` (a dotted path reaches into a table: ``gains.lookahead``)."""
    try:
        return lookup(params, name)
    except KeyError:
        raise no_param(node, name, names(params)) from None


def names(params: dict[str, Any], prefix: str = "") -> list[str]:
    """Every parameter's name, tables' entries dotted (``gains.lookahead``), in the node's order."""
    out = []
    for key, item in params.items():
        if isinstance(item, dict):
            out += names(item, f"{prefix}{key}.")
        else:
            out.append(prefix + key)
    return out


def parse_details(node: str, answers: list[Any]) -> NodeDetails:
    """What ``node`` says about itself, from the answers to ``turtlectl/nodes/<node>`` (the
    last JSON one); Failed if there is none or it does not read."""
    raw = [a for a in answers if isinstance(a, Raw)]
    if not raw:
        raise Failed(f"{node} did not say what it is")
    try:
        return msgspec.json.decode(raw[-1].payload, type=NodeDetails)
    except msgspec.DecodeError as exc:
        raise Failed(f"{node} sent an unreadable answer: {exc}") from None
