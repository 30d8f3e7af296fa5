"""What a node answers about itself, read: its parameters (``turtlectl/params/<node>``) and its
details (``turtlectl/nodes/<node>``).  Pure: no session; Failed or BadInput for an answer that
does not read or a parameter it does not have.
"""

from __future__ import annotations

from typing import Any

import msgspec

from turtlectl.messages.keys import NodeDetails
from turtlectl.runtime.client.errors import BadInput, Failed, Unreachable
from turtlectl.runtime.client.graph import Graph
from turtlectl.runtime.client.services import NobodyServes, Raw
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


def no_node(node: str, running: list[str], domain: str, hint: str = "") -> NobodyServes:
    """No node called ``node`` answers in this command's domain (the running node nearest its
    name suggested: ``param``, ``node info``, ``log-level`` all come here); ``hint``: where
    systems run when none runs here (the live graph's hint)."""
    where = f" in domain {domain}" if domain else ""
    found = f"running: {', '.join(sorted(running))}" if running else f"no node runs{where}"
    near = suggestion(node, running)
    return NobodyServes(
        f"no node named {node!r} answers{where}{near} ({found}){'; ' + hint if hint and not running else ''}"
    )


class Silent(Unreachable):
    """A node that runs (its liveliness token is in the graph) gave no answer: its thread is
    busy or blocked, or it is stopping (exit code 3, as a node that does not run)."""


def unanswered(
    node: str, graph: Graph, domain: str, what: str, waited: float | None = None, after: str = ""
) -> Unreachable:
    """Why ``node`` gave no answer ``what`` (``with its parameters``): it does not run
    (NobodyServes naming the live nodes), or it runs (Silent, with its pid and host from
    ``graph``) and did not answer within ``waited`` s (None: nothing served the key, the
    query ended at once).  ``after``: what the user should know besides (a change that may
    still apply)."""
    row = next((n for n in graph.nodes if n.name == node), None)
    if row is None:
        return no_node(node, [n.name for n in graph.nodes], domain, graph.hint)
    within = f" within {waited:g} s" if waited is not None else ""
    why = (
        "its thread is busy or blocked (a callback that has not returned?)"
        if waited is not None
        else "it serves nothing there now (is it stopping?)"
    )
    return Silent(
        f"{node} runs (pid {row.pid}, host {row.host}) but did not answer {what}{within}: {why}"
        f"{'; ' + after if after else ''}; `turtlectl log --node {node}` shows its last lines"
    )
