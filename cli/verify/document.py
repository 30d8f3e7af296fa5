"""A specification written out: as the capstone's Markdown template (``markdown``: intent,
nodes with their inputs, outputs and purpose, interfaces, success criteria as unchecked
boxes "- [ ]" (a printed specification is no measured system: ``verify`` gives verdicts),
non-goals as a list) and as a TOML file ``parse_spec`` reads back (``to_toml``); and the skeleton of a
specification made from a live graph and the periods measured on it (``skeleton``).  Pure:
strings in, strings out, no session."""

from __future__ import annotations

import json
import math
import re
from typing import Any

import msgspec

from turtlectl.cli.verify.spec import Criterion, NodeSpec, Parameters, Period, ServiceSpec, Spec, TopicSpec, label
from turtlectl.runtime.client.graph import Graph, under

#: what a skeleton says where a person must write
INTENT_PLACEHOLDER = "TODO: what the system is for"
PURPOSE_PLACEHOLDER = "TODO: what this node is for"


# -- Markdown ----------------------------------------------------------------------------------


def _numbers(criterion: Any) -> str:
    """The criterion's wording (its name, or what ``label`` makes of it), with its numbers
    beside a name that is the author's own."""
    named = label(criterion)
    plain = label(msgspec.structs.replace(criterion, name="")) if criterion.name else named
    return named if plain == named else f"{named} ({plain})"


def _listed(keys: list[str], none: str) -> str:
    return ", ".join(f"`{k}`" for k in keys) if keys else none


def _frequency(topic: TopicSpec) -> str:
    if topic.period_ms is None:
        return "not specified"
    hz = f"{1000 / topic.period_ms:.3g} Hz, " if topic.period_ms > 0 else ""
    return f"{hz}every {topic.period_ms:g} ms (± {topic.tolerance_ms:g} ms)"


def _topic(spec: Spec, topic: TopicSpec) -> list[str]:
    publishers = [topic.publisher] if topic.publisher else [n.name for n in spec.node if topic.key in n.outputs]
    subscribers = [n.name for n in spec.node if topic.key in n.inputs]
    return [
        f"### Topic: {topic.key}",
        f"Message Type: {topic.type}",
        f"Frequency: {_frequency(topic)}",
        f"Publishers: {', '.join(publishers) or 'any node'}",
        f"Subscribers: {', '.join(subscribers) or 'none declared'}",
        "",
    ]


def _service(service: ServiceSpec) -> list[str]:
    return [
        f"### Service: {service.key}",
        f"Request: {service.request}",
        f"Response: {service.response or 'not specified'}",
        f"Server: {service.server or 'any node'}",
        "",
    ]


def markdown(spec: Spec, title: str = "Specification") -> str:
    """``spec`` as the capstone's template: Intent, System Architecture (each node's input,
    output and purpose), Interfaces (each service and topic: types, frequency, who publishes
    and who subscribes), Success Criteria (an unchecked box "- [ ]" each, with its numbers: no
    verdict before ``verify`` has measured one), Non-Goals ("- " each)."""
    lines = [f"# {title}", "", "## Intent", spec.intent.strip(), "", "## System Architecture", ""]
    for node in spec.node:
        lines += [
            f"### {node.name}",
            f"Input: {_listed(node.inputs, 'none')}",
            f"Output: {_listed(node.outputs, 'none')}",
            f"Purpose: {node.purpose or 'not specified'}",
            "",
        ]
    if not spec.node:
        lines += ["No nodes declared.", ""]
    lines += ["## Interfaces", ""]
    for service in spec.service:
        lines += _service(service)
    for topic in spec.topic:
        lines += _topic(spec, topic)
    if not spec.service and not spec.topic:
        lines += ["No topics or services declared.", ""]
    lines += ["## Success Criteria", ""]
    lines += [f"- [ ] {_numbers(c)}" for c in spec.criterion] or ["No criteria declared."]
    lines += ["", "## Non-Goals", ""]
    lines += [f"- {g}" for g in spec.non_goals] or ["None declared."]
    return "\n".join(lines) + "\n"


# -- TOML --------------------------------------------------------------------------------------


def _string(text: str) -> str:
    """A TOML basic string: JSON's escapes are TOML's, but for DEL, which TOML wants escaped."""
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return _string(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        return repr(value) if math.isfinite(value) else ("inf" if value > 0 else "-inf")
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    if isinstance(value, msgspec.Struct):
        return "{ " + ", ".join(f"{k} = {_value(v)}" for k, v in _fields(value)) + " }"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{_string(str(k))} = {_value(v)}" for k, v in value.items()) + " }"
    raise TypeError(f"no TOML for {type(value).__name__}")


def _fields(item: msgspec.Struct) -> list[tuple[str, Any]]:
    """An item's tag (``check = "period"``) and the fields that differ from their defaults."""
    config = item.__struct_config__
    out: list[tuple[str, Any]] = [(config.tag_field, config.tag)] if config.tag_field else []
    for field in msgspec.structs.fields(item):
        value = getattr(item, field.name)
        default = field.default_factory() if field.default_factory is not msgspec.NODEFAULT else field.default
        if value is None or (default is not msgspec.NODEFAULT and value == default):
            continue
        out.append((field.encode_name, value))
    return out


def to_toml(spec: Spec) -> str:
    """``spec`` as a TOML file ``parse_spec`` reads back as it is: the top-level keys (each
    written, empty or not), then each list of items as an array of tables, every item with
    the fields that differ from their defaults."""
    lines: list[str] = []
    tables: list[tuple[str, list[msgspec.Struct]]] = []
    for field in msgspec.structs.fields(spec):
        value = getattr(spec, field.name)
        if isinstance(value, list) and value and all(isinstance(v, msgspec.Struct) for v in value):
            tables.append((field.encode_name, value))
        elif isinstance(value, list) and field.name != "non_goals" and not value:
            continue  # an empty list of items: nothing to write
        elif value is not None:
            lines.append(f"{field.encode_name} = {_value(value)}")
    for name, items in tables:
        for item in items:
            lines += ["", f"[[{name}]]"]
            fields = _fields(item)
            lines += [f"{k} = {_value(v)}" for k, v in fields if not _by_name(v)]
            for k, v in fields:  # a table of tables (a parameters criterion's nodes): one sub-table each
                if _by_name(v):
                    for key, table in v.items():
                        lines += ["", f"[{name}.{k}.{_key(key)}]"]
                        lines += [f"{_key(sub)} = {_value(value)}" for sub, value in table.items()]
    return "\n".join(lines) + "\n"


def _by_name(value: Any) -> bool:
    """A non-empty table of tables (``params``: each node's parameters)."""
    return isinstance(value, dict) and bool(value) and all(isinstance(v, dict) and v for v in value.values())


def _key(name: str) -> str:
    """A TOML key: bare when it can be, else a quoted string (``"turtle2/navigator"``)."""
    return name if re.fullmatch(r"[A-Za-z0-9_-]+", name) else _string(name)


# -- a skeleton from the live graph ------------------------------------------------------------


def _two_figures(value: float) -> float:
    return round(value, 1 - math.floor(math.log10(value)))


def rounded_period(mean_ms: float) -> float:
    """A measured period (ms) as a specification states it: the period or the rate
    rounded to two significant figures, whichever is nearer (99.7 ms -> 100.0, 16.02 ms ->
    16.0, 33.4 ms -> 33.3 from 30 Hz), to 0.1 ms."""
    by_period = round(_two_figures(mean_ms), 1)
    by_rate = round(1000 / _two_figures(1000 / mean_ms), 1)
    return min(by_period, by_rate, key=lambda p: (abs(p - mean_ms), p))


def skeleton(
    graph: Graph, periods: dict[str, tuple[float, float]], params: dict[str, dict[str, Any]] | None = None
) -> Spec:
    """A specification to edit into a real one, from ``graph`` (without each node's own
    services), ``periods`` (a topic's key: its period and tolerance, ms, as measured) and
    ``params`` (each node's parameters as it runs with them):
    a placeholder intent, each node with what it takes in (keys it subscribes to or serves)
    and puts out (keys it publishes), each published topic with its type, its publisher
    (when there is one) and its period, each service with its request type and server, a
    period criterion for each measured topic, a parameters criterion with each node's values
    (those TOML can write), no non-goals."""
    used = [t for t in graph.topics if not under(t.key)]  # not the runtime's own (parameter events)
    topics = [t for t in used if t.publishers]
    nodes = [
        NodeSpec(
            name=n.name,
            purpose=PURPOSE_PLACEHOLDER,
            inputs=sorted(
                {t.key for t in used if n.name in t.subscribers}
                | {s.key for s in graph.services if n.name in s.servers}
            ),
            outputs=sorted(t.key for t in used if n.name in t.publishers),
        )
        for n in sorted(graph.nodes, key=lambda n: n.name)
    ]
    topic_specs = []
    for t in topics:
        publisher = t.publishers[0] if len(t.publishers) == 1 else ""
        if t.key in periods:
            period, tolerance = periods[t.key]
            topic_specs.append(
                TopicSpec(key=t.key, type=t.type, publisher=publisher, period_ms=period, tolerance_ms=tolerance)
            )
        else:
            topic_specs.append(TopicSpec(key=t.key, type=t.type, publisher=publisher))
    services = [
        ServiceSpec(key=s.key, request=s.type, server=s.servers[0] if len(s.servers) == 1 else "")
        for s in graph.services
    ]
    criteria: list[Criterion] = [
        Period(key=t.key, period_ms=t.period_ms, tolerance_ms=t.tolerance_ms)
        for t in topic_specs
        if t.period_ms is not None
    ]
    stated = {node: {k: v for k, v in values.items() if v is not None} for node, values in (params or {}).items()}
    stated = {node: values for node, values in sorted(stated.items()) if values}
    if stated:
        criteria.append(Parameters(params=stated))
    return Spec(
        intent=INTENT_PLACEHOLDER,
        node=nodes,
        topic=topic_specs,
        service=services,
        criterion=criteria,
        non_goals=[],
    )
