"""``turtlectl param``: a running node's parameters, as ``ros2 param list / get / set /
describe / dump``.  Each node answers a get on ``turtlectl/params/<name>`` with its
parameters as JSON (the launch file's ``[node.params]`` after validation), on
``turtlectl/params/<name>/describe`` with their description (messages.params), and changes
one on ``turtlectl/params/<name>/set``.  Everything here works from those answers alone, so
a node of a kind this command line does not know (a user's own) works as the built-in ones
do; a node of a kind a launch file runs is also held to the launch file's rules.  This module
fetches, validates and shapes, and prints nothing itself."""

from __future__ import annotations

import json
from typing import Any

import msgspec

from turtlectl.messages import Ack, SetParameter
from turtlectl.messages.keys import NodeDetails, node_key, node_name, param_describe_key, param_set_key, params_key
from turtlectl.messages.params import ParamDescription, ParamInfo
from turtlectl.messages.world import World
from turtlectl.runtime.client.answers import names, no_param, parse_params, unanswered
from turtlectl.runtime.client.errors import BadInput, Failed, Unreachable
from turtlectl.runtime.client.services import (
    NoAnswer,
    NobodyServes,
    Raw,
    Rejected,
    call_service,
    replies,
    service_session,
    world,
)

#: s a node has to answer
TIMEOUT = 3.0


def silent(
    connect: str, domain: str, node: str, what: str, exc: Unreachable | NoAnswer, after: str = ""
) -> Unreachable:
    """``unanswered`` for a call that raised ``exc``, against the live graph now."""
    from turtlectl.cli.tools import topics

    waited = exc.timeout if isinstance(exc, NoAnswer) else None
    return unanswered(node, topics.graph(connect, domain), domain, what, waited, after)


def _served(connect: str, domain: str, key: str, node: str, what: str) -> bytes:
    """``node``'s JSON answer on ``key``.  NobodyServes (exit 3) naming the live nodes if no
    node of that name runs; Silent (exit 3) if it runs but does not answer."""
    try:
        answers = list(call_service(connect, domain, key, b"", TIMEOUT))
    except NobodyServes as exc:
        raise silent(connect, domain, node, f"with {what}", exc) from None
    except NoAnswer as exc:
        if exc.answered:
            raise
        raise silent(connect, domain, node, f"with {what}", exc) from None
    if not answers or not isinstance(answers[-1], Raw):
        raise Failed(f"{node} answered, but not {what}")
    return answers[-1].payload


def fetch(connect: str, domain: str, node: str) -> dict[str, Any]:
    """The parameters ``node`` runs with (NobodyServes naming the live nodes)."""
    return parse_params(node, _served(connect, domain, params_key(node), node, "its parameters"))


def description(connect: str, domain: str, node: str) -> ParamDescription:
    """What ``node`` serves about its parameters, whatever its kind (NobodyServes naming the
    live nodes)."""
    try:
        return msgspec.json.decode(
            _served(connect, domain, param_describe_key(node), node, "its parameters' description"),
            type=ParamDescription,
        )
    except (msgspec.DecodeError, msgspec.ValidationError) as exc:
        raise Failed(f"{node} sent an unreadable description of its parameters: {exc}") from None


def _entries(described: ParamDescription, name: str) -> list[str]:
    """The parameters inside table ``name`` (``gains`` -> ``gains.lookahead``, ...)."""
    inside = [p.name for p in described.parameters if p.name.startswith(name + ".")]
    here = next((p for p in described.parameters if p.name == name), None)
    if here is not None and isinstance(here.value, dict):  # a map: its keys now
        inside += names(here.value, name + ".")
    return inside


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


class Running(msgspec.Struct):
    """What runs now: each node's details and parameters (by name), and the world."""

    details: dict[str, NodeDetails]
    params: dict[str, dict[str, Any]]
    world: World


def _answers(session: Any, key: str) -> dict[str, bytes]:
    """Each node's JSON answer on ``key`` (ending in ``*``), by node name; none: {}.  A node
    that does not answer in time (its thread busy) is left out, the others kept."""
    got: dict[str, bytes] = {}
    try:
        for answer in replies(session, key, b"", TIMEOUT, everyone=True):
            if isinstance(answer, Raw):
                got[node_name(answer.key.rsplit("/", 1)[-1])] = answer.payload
    except (NobodyServes, NoAnswer):
        pass
    return got


def running(connect: str, domain: str) -> Running:
    """Every running node's details and parameters, and the world (NobodyServes: no node)."""
    with service_session(connect, domain) as session:
        details = {
            name: msgspec.json.decode(body, type=NodeDetails) for name, body in _answers(session, node_key("*")).items()
        }
        if not details:
            raise NobodyServes("no node is running", "is `turtlectl launch` running?")
        params = {name: msgspec.json.decode(body) for name, body in _answers(session, params_key("*")).items()}
        return Running(details=details, params=params, world=world(session))


def describe(connect: str, domain: str, node: str, name: str) -> tuple[ParamInfo, Any]:
    """Parameter ``name`` of ``node``: type, unit, range, default, meaning, whether it can
    change at run time; and its value now (as the node describes them)."""
    described = description(connect, domain, node)
    infos = {p.name: p for p in described.parameters}
    entries = _entries(described, name)
    if name not in infos and entries:
        raise BadInput(f"{node} {name} is a table: describe one of its entries ({', '.join(entries)})")
    if name not in infos:
        raise no_param(node, name, list(infos))
    return infos[name], infos[name].value


def plain(info: ParamInfo) -> dict[str, Any]:
    return msgspec.to_builtins(info)


def describe_text(node: str, info: ParamInfo, now: Any) -> str:
    live = "yes" if info.run_time else f"no: {info.fixed_because}"
    return "\n".join(
        [
            f"{node} {info.name}",
            f"  value:       {msgspec.json.encode(now).decode()}",
            f"  type:        {info.type}",
            f"  unit:        {info.unit}",
            f"  range:       {info.range}",
            f"  default:     {info.default}",
            f"  meaning:     {info.meaning}",
            f"  at run time: {live}",
        ]
    )


def _check_value(node: str, kind: str, now: dict[str, Any], name: str, text: str) -> None:
    """The value itself (its type and range), checked here as the node would check it
    (runtime.params), so that a built-in node's refusal reads as a user node's does:
    ``navigator: goal_timeout must be >= 0.1 (got -1)``."""
    from turtlectl.cli.system.overrides import parse_assignment
    from turtlectl.nodes.kinds import KINDS
    from turtlectl.runtime.params import ParamRefused, with_value

    value = parse_assignment(f"{node}.{name}={text}", "param set", "param set NODE NAME VALUE").value
    try:
        params = msgspec.convert(now, KINDS[kind].params, strict=True)
    except msgspec.ValidationError:
        return  # what it runs with does not read back: the launch file's checks will say why
    try:
        with_value(params, name, value)
    except ParamRefused as exc:
        raise BadInput(f"{node}: {exc}") from None


def set_value(connect: str, domain: str, node: str, name: str, text: str, timeout: float = TIMEOUT) -> str:
    """Set ``node``'s parameter ``name`` to ``text`` (a TOML value, else the text), checked
    against what the node describes (unknown names, tables, what cannot change at run time,
    refused with the reason); a node of a kind a launch file runs is validated first as
    ``launch --set`` validates a launch file (same errors, exit 2), against what runs now (a
    detector's new rate is checked against the navigator's scan_timeout), its value itself
    first as the node checks it.  The node validates the value itself (its type and range;
    exit 2): its refusal is its one line (``mine: rate must be <= 50 (got 60)``), the same
    wording as a built-in kind's.  Returns the node's answer."""
    from turtlectl.cli.system.launchfile import suggestion
    from turtlectl.cli.system.overrides import launches, parse_assignment, running_change

    described = description(connect, domain, node)
    infos = {p.name: p for p in described.parameters}
    entries = _entries(described, name)
    if entries:
        raise BadInput(f"param set {node}.{name}: is a table: set one of its entries ({', '.join(entries)})")
    info = infos.get(name)
    if launches(described.kind):
        system = running(connect, domain)
        if info is not None and info.run_time and node in system.params:
            _check_value(node, described.kind, system.params[node], name, text)
        nodes = {n: (d.kind, system.params[n]) for n, d in system.details.items() if n in system.params}
        new = running_change(nodes, system.world, node, name, text, "param set")
    elif name not in infos:
        known = list(infos)
        raise BadInput(f"param set {node}.{name}: unknown key{suggestion(name, known)} (it has: {', '.join(known)})")
    else:
        new = parse_assignment(f"{node}.{name}={text}", "param set", "param set NODE NAME VALUE").value
    if info is not None and not info.run_time:
        raise BadInput(f"param set {node}.{name}: cannot change while {node} runs: {info.fixed_because}")
    request = SetParameter(name=name, value=new)
    try:
        answers = list(call_service(connect, domain, param_set_key(node), request, timeout))
    except Rejected as exc:  # the node's own check (runtime.params): its one line, as _check_value's
        raise BadInput(exc.reason) from None
    except (NobodyServes, NoAnswer) as exc:
        if isinstance(exc, NoAnswer) and exc.answered:
            raise
        # the request waits in its queue: its thread applies it once free
        raise silent(connect, domain, node, f"to set {name}", exc, "the change may still apply once it does") from None
    acks = [a for a in answers if isinstance(a, Ack)]
    if not acks:
        raise Failed(f"{node} did not confirm the change")
    return acks[-1].detail


def listing_all(connect: str, domain: str) -> dict[str, list[str]]:
    """Every running node's parameter names, by node (``param list`` without NODE)."""
    system = running(connect, domain)
    return {node: names(system.params[node]) for node in sorted(system.params)}


def listing_text(by_node: dict[str, list[str]]) -> str:
    return "\n".join(f"{node}:\n" + "\n".join(f"  {n}" for n in names_) for node, names_ in by_node.items())
