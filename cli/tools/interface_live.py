"""``turtlectl interface show`` of a type the running nodes use (pure: no zenoh): its fields
read from the JSON Schema of its description (messages.described) as a built-in's are from
its class: Python-like types (``list[Point]``, ``Point | None``), ``required`` or the
default, the values or range, and its keys from the live graph.  A Struct nested in a live
type (in the schema's ``$defs``) is shown from its definition."""

from __future__ import annotations

from typing import Any

import msgspec

from turtlectl.messages.codec import MEDIA_TYPE
from turtlectl.messages.described import TypeDescription
from turtlectl.runtime.client.graph import Graph
from turtlectl.runtime.params import range_text

Live = dict[str, dict[str, TypeDescription]]  # type name -> node -> its description
_SCALARS = {"number": "float", "integer": "int", "string": "str", "boolean": "bool", "null": "None"}
_BOUNDS = {"minimum": "ge", "exclusiveMinimum": "gt", "maximum": "le", "exclusiveMaximum": "lt"}


def _ref(prop: dict[str, Any]) -> str:
    return str(prop["$ref"]).rsplit("/", 1)[-1]


def py_type(prop: dict[str, Any]) -> str:
    """A field's type as Python writes it, from its JSON Schema: ``int``, ``bytes``,
    ``list[Point]``, ``tuple[float, float]``, ``dict[str, int]``, ``Point | None``; a Struct
    or an enum by its name; ``any`` for an untyped field."""
    if "$ref" in prop:
        return _ref(prop)
    if "anyOf" in prop:
        return " | ".join(py_type(p) for p in prop["anyOf"])
    if "enum" in prop:
        return " | ".join(sorted({_SCALARS.get(_json_kind(v), "any") for v in prop["enum"]}))
    kind = prop.get("type")
    if kind == "string" and prop.get("contentEncoding") == "base64":
        return "bytes"
    if kind == "array":
        if "prefixItems" in prop:
            return f"tuple[{', '.join(py_type(p) for p in prop['prefixItems'])}]"
        return f"list[{py_type(prop['items'])}]" if isinstance(prop.get("items"), dict) else "list"
    if kind == "object":
        extra = prop.get("additionalProperties")
        return f"dict[str, {py_type(extra)}]" if isinstance(extra, dict) else "dict"
    return _SCALARS.get(str(kind), "any")


def _json_kind(value: Any) -> str:
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, int):
        return "integer"
    if isinstance(value, float):
        return "number"
    return "null" if value is None else "string"


def range_of(prop: dict[str, Any], defs: dict[str, Any]) -> str:
    """The values a field takes: an enum's (``left, right``), a number's bounds (as
    runtime.params.range_text words them: ``> 0 and <= 8``), a list's most items, else ``any``."""
    if "$ref" in prop:
        target = defs.get(_ref(prop), {})
        return range_of(target, defs) if "enum" in target else "any"
    if "anyOf" in prop:
        ranges = [range_of(p, defs) for p in prop["anyOf"] if p.get("type") != "null"]
        return ranges[0] if len(ranges) == 1 else "any"
    if "enum" in prop:
        return ", ".join(str(v) for v in prop["enum"])
    kind = prop.get("type")
    bounds = {key: prop[name] for name, key in _BOUNDS.items() if name in prop}
    if kind in ("number", "integer") and bounds:
        t = msgspec.inspect.FloatType(**bounds) if kind == "number" else msgspec.inspect.IntType(**bounds)
        return range_text(t)
    if kind == "array" and "prefixItems" not in prop and "maxItems" in prop:
        return range_text(msgspec.inspect.ListType(msgspec.inspect.AnyType(), max_length=prop["maxItems"]))
    return "any"


def default_of(name: str, prop: dict[str, Any], required: set[str]) -> str:
    """``required``, or the default as a built-in's is written (``0``, ``1.5``, ``"left"``)."""
    if name in required:
        return "required"
    value = prop.get("default")
    if isinstance(value, float):
        return f"{value:.8g}"
    return msgspec.json.encode(value).decode()


def fields_of(body: dict[str, Any], defs: dict[str, Any], said: dict[str, tuple[str, str]]) -> list[dict[str, Any]]:
    """The rows of one Struct's definition (``body``, from ``$defs``); ``said``: field ->
    (unit, meaning) where the description gives them (a nested Struct's fields have none)."""
    props: dict[str, Any] = body.get("properties", {})
    required = set(body.get("required", ()))
    names = list(said) if said else [n for n in props if n != "type" or "enum" not in props[n]]
    rows = []
    for name in names:
        prop = props.get(name, {})
        unit, meaning = said.get(name, ("", prop.get("description", "")))
        rows.append(
            {
                "name": name,
                "type": py_type(prop),
                "default": default_of(name, prop, required),
                "unit": unit or "-",
                "range": range_of(prop, defs),
                "meaning": meaning,
            }
        )
    return rows


def live_description(said: dict[str, TypeDescription], keys: list[str], conflict: str = "") -> dict[str, Any]:
    """A live message type in full (``interface show``), from what its nodes ``said`` (and
    how they disagree: ``conflict``)."""
    first = next(iter(said.values()))
    defs = first.schema.get("$defs", {})
    body = defs.get(_ref(first.schema), {})
    units = {f.name: (f.unit, f.meaning) for f in first.fields}
    described = {
        "type": first.name,
        "encoding": f"{MEDIA_TYPE};{first.name}",
        "keys": keys,
        "doc": first.doc,
        "fields": fields_of(body, defs, units) if units else [],
        "hash": first.hash,
        "nodes": sorted(said),
    }
    if conflict:
        described["conflict"] = conflict
    return described


def nested_description(name: str, live: Live) -> dict[str, Any] | None:
    """A Struct (or enum) nested in the live types (``$defs`` of their schemas), any case,
    from its definition; None when no live type has one of that name."""
    found: dict[str, Any] | None = None
    for parent, said in sorted(live.items()):
        first = next(iter(said.values()))
        defs = first.schema.get("$defs", {})
        for def_name, body in defs.items():
            if def_name.lower() != name.lower() or def_name == _ref(first.schema):
                continue
            if found is None:
                values = ", ".join(str(v) for v in body.get("enum", ()))
                doc = body.get("description") or (f"An enum: one of {values}." if values else "")
                what = "an enum" if values else "a map"
                found = {"type": def_name, "what": what, "nested_in": [], "keys": [], "doc": doc}
                found["fields"] = fields_of(body, defs, {})
            found["nested_in"].append(parent)
    return found


def keys_by_type(graph: Graph) -> dict[str, list[str]]:
    """Type name -> the keys that carry it in the live graph: topics, and services by their
    request type."""
    keys: dict[str, list[str]] = {}
    for row in [*graph.topics, *graph.services]:
        keys.setdefault(row.type, []).append(row.key)
    return {name: sorted(set(found)) for name, found in keys.items()}
