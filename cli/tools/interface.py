"""``turtlectl interface``: the message types of the wire contract, as ``ros2 interface
list / show``.  Builds values and text from messages.reference (units, ranges, meanings,
keys); prints nothing itself."""

from __future__ import annotations

from typing import Any

from turtlectl.cli.tools.build import type_named
from turtlectl.messages import ALL_TYPES
from turtlectl.messages.codec import encoding_for, type_name
from turtlectl.messages.reference import FIELDS, KEYS, default_text, doc, struct_fields
from turtlectl.messages.reference import type_name as field_type


def _keys_of(name: str) -> list[str]:
    """The keys (topics and services) whose payload is the type ``name``."""
    return [key for key, (kind, payload, *_) in KEYS.items() if kind != "queryable" and name in payload.split()]


def summary(cls: type) -> str:
    """The first paragraph of a type's documentation on one line: its whole first sentence,
    however many source lines it spans."""
    return " ".join(doc(cls).split("\n\n", 1)[0].split())


def listing() -> list[dict[str, Any]]:
    """Every message type: its name, the keys that carry it, and its summary."""
    return [{"type": type_name(t), "keys": _keys_of(type_name(t)), "summary": summary(t)} for t in ALL_TYPES]


def listing_text(rows: list[dict[str, Any]]) -> str:
    width = max(len(r["type"]) for r in rows)
    lines = [
        f"{r['type']:{width}}  {r['summary']}" + (f"  [{', '.join(r['keys'])}]" if r["keys"] else "") for r in rows
    ]
    return "\n".join(lines + ["", "turtlectl interface show TYPE: its fields, units and defaults"])


def description(name: str) -> dict[str, Any]:
    """One type in full: wire tag and encoding, the keys that carry it, its documentation and
    every field (type, default, unit, range, meaning).  BadInput for a name that is no type."""
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


def description_text(d: dict[str, Any]) -> str:
    head = [
        f'{d["type"]}: msgpack map tagged "type": "{d["type"]}" (encoding {d["encoding"]})',
        f"keys: {', '.join(d['keys']) or '(none of its own)'}",
        "",
        d["doc"],
        "",
    ]
    rows = [("field", "type", "default", "unit", "range / values")] + [
        (f["name"], f["type"], f["default"], f["unit"], f["range"]) for f in d["fields"]
    ]
    widths = [max(len(r[k]) for r in rows) for k in range(4)]
    table = ["  ".join(cell.ljust(w) for cell, w in zip(r[:4], widths, strict=True)) + "  " + r[4] for r in rows]
    meanings = [f"  {f['name']}: {f['meaning']}" for f in d["fields"]]
    return "\n".join(head + table + (["", "meaning:"] + meanings if meanings else ["(no fields)"]))
