"""``turtlectl interface``: the message types of the wire contract, as ``ros2 interface
list / show``: the built-ins (messages.reference: units, ranges, meanings, keys) and, when a
system runs, every other type its nodes use, from the descriptions they serve
(messages.described), with the nodes that use each and any conflict; prints nothing itself."""

from __future__ import annotations

from typing import Any

import msgspec

from turtlectl.cli.errors import Unreachable
from turtlectl.cli.tools.build import type_named
from turtlectl.cli.tools.typebook import conflict
from turtlectl.messages import ALL_TYPES
from turtlectl.messages.codec import MEDIA_TYPE, encoding_for, type_name
from turtlectl.messages.described import TypeDescription
from turtlectl.messages.reference import FIELDS, KEYS, default_text, doc, struct_fields
from turtlectl.messages.reference import type_name as field_type


def _keys_of(name: str) -> list[str]:
    """The keys (topics and services) whose payload is the type ``name``."""
    return [key for key, (kind, payload, *_) in KEYS.items() if kind != "queryable" and name in payload.split()]


def summary(cls: type) -> str:
    """The first paragraph of a type's documentation on one line: its whole first sentence,
    however many source lines it spans."""
    return " ".join(doc(cls).split("\n\n", 1)[0].split())


Live = dict[str, dict[str, TypeDescription]]  # type name -> node -> its description


def live_types(connect: str, domain: str | None = None) -> Live:
    """What the running system's nodes say of the types they use ({} when none runs)."""
    from turtlectl.cli.tools.client import client_session
    from turtlectl.cli.tools.typebook import descriptions

    try:
        with client_session(connect, domain) as session:
            return descriptions(session)
    except Unreachable:
        return {}


def is_builtin(name: str) -> bool:
    return any(type_name(t).lower() == name.lower() for t in ALL_TYPES)


def listing(live: Live | None = None) -> list[dict[str, Any]]:
    """Every message type: its name, the keys that carry it, and its summary; then the types
    the running nodes use besides (``live``), with those nodes and any conflict."""
    rows = [{"type": type_name(t), "keys": _keys_of(type_name(t)), "summary": summary(t)} for t in ALL_TYPES]
    builtin = {r["type"] for r in rows}
    for name, said in sorted((live or {}).items()):
        if name in builtin:
            continue
        first = next(iter(said.values()))
        row = {"type": name, "keys": [], "summary": first.doc, "nodes": sorted(said)}
        if conflict(said):
            row["conflict"] = conflict(said)
        rows.append(row)
    return rows


def listing_text(rows: list[dict[str, Any]]) -> str:
    width = max(len(r["type"]) for r in rows)
    lines = [
        f"{r['type']:{width}}  {r['summary']}"
        + (f"  [{', '.join(r['keys'])}]" if r["keys"] else "")
        + (f"  (used by {', '.join(r['nodes'])})" if r.get("nodes") else "")
        + (f"  CONFLICT: {r['conflict']}" if r.get("conflict") else "")
        for r in rows
    ]
    return "\n".join(lines + ["", "turtlectl interface show TYPE: its fields, units and defaults"])


def description(name: str, live: Live | None = None) -> dict[str, Any]:
    """One type in full: wire tag and encoding, the keys that carry it, its documentation and
    every field (type, default, unit, range, meaning).  A type the running nodes use (``live``)
    from its description.  BadInput for a name that is no type."""
    said = next((s for n, s in (live or {}).items() if n.lower() == name.lower()), None)
    if said is not None and not any(type_name(t).lower() == name.lower() for t in ALL_TYPES):
        return _described(said)
    cls = type_named(name)
    tag = type_name(cls)
    fields = []
    for f in struct_fields(cls):
        unit, span, meaning = FIELDS[tag][f.name]
        fields.append(
            {
                "name": f.name,
                "type": field_type(f.type),
                "default": default_text(f),
                "unit": unit,
                "range": span,
                "meaning": meaning,
            }
        )
    return {
        "type": tag,
        "encoding": encoding_for(cls),
        "keys": _keys_of(tag),
        "doc": doc(cls),
        "fields": fields,
    }


def _described(said: dict[str, TypeDescription]) -> dict[str, Any]:
    first = next(iter(said.values()))
    body = first.schema["$defs"][first.schema["$ref"].rsplit("/", 1)[-1]]
    props = body.get("properties", {})
    required = set(body.get("required", ()))
    fields = [
        {
            "name": f.name,
            "type": f.type,
            "default": "" if f.name in required else msgspec.json.encode(props.get(f.name, {}).get("default")).decode(),
            "unit": f.unit or "-",
            "range": "",
            "meaning": f.meaning,
        }
        for f in first.fields
    ]
    described = {
        "type": first.name,
        "encoding": f"{MEDIA_TYPE};{first.name}",
        "keys": [],
        "doc": first.doc,
        "fields": fields,
        "hash": first.hash,
        "nodes": sorted(said),
    }
    if conflict(said):
        described["conflict"] = conflict(said)
    return described


def description_text(d: dict[str, Any]) -> str:
    head = [
        f'{d["type"]}: msgpack map tagged "type": "{d["type"]}" (encoding {d["encoding"]})',
        f"keys: {', '.join(d['keys']) or '(none of its own)'}",
    ]
    if d.get("nodes"):
        head.append(f"described by: {', '.join(d['nodes'])} (hash {d['hash']})")
    if d.get("conflict"):
        head.append(f"CONFLICT: {d['conflict']}")
    head += ["", d["doc"], ""]
    rows = [("field", "type", "default", "unit", "range / values")] + [
        (f["name"], f["type"], f["default"], f["unit"], f["range"]) for f in d["fields"]
    ]
    widths = [max(len(r[k]) for r in rows) for k in range(4)]
    table = ["  ".join(cell.ljust(w) for cell, w in zip(r[:4], widths, strict=True)) + "  " + r[4] for r in rows]
    meanings = [f"  {f['name']}: {f['meaning']}" for f in d["fields"]]
    return "\n".join(head + table + (["", "meaning:"] + meanings if meanings else ["(no fields)"]))
