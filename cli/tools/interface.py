"""``turtlectl interface``: the message types of the wire contract, as ``ros2 interface
list / show``: the built-ins (messages.reference: units, ranges, meanings, keys) and, when a
system runs, every other type its nodes use, from the descriptions they serve
(messages.described), with the nodes that use each and any conflict; prints nothing itself."""

from __future__ import annotations

from typing import Any

from turtlectl.cli.tools.build import which_type
from turtlectl.cli.tools.interface_live import Live, keys_by_type, live_description, nested_description
from turtlectl.messages import ALL_TYPES
from turtlectl.messages.codec import encoding_for, type_name, type_short_name
from turtlectl.messages.fieldtext import default_text, doc, struct_fields
from turtlectl.messages.fieldtext import type_name as field_type
from turtlectl.messages.key_reference import KEYS
from turtlectl.messages.reference import FIELDS
from turtlectl.runtime.client.errors import BadInput, Unreachable
from turtlectl.runtime.client.typebook import conflict


def _keys_of(cls: type) -> list[str]:
    """The keys (topics and services) whose payload is the built-in type ``cls`` (the key
    reference names them short)."""
    name = type_short_name(cls)
    return [key for key, (kind, payload, *_) in KEYS.items() if kind != "queryable" and name in payload.split()]


def summary(cls: type) -> str:
    """The first paragraph of a type's documentation on one line: its whole first sentence,
    however many source lines it spans."""
    return " ".join(doc(cls).split("\n\n", 1)[0].split())


Keys = dict[str, list[str]]  # type name -> the keys that carry it in the live graph


def live_types(connect: str, domain: str) -> tuple[Live, Keys]:
    """What the running system's nodes say of the types they use, and the keys (topics and
    services) that carry each in the live graph (both {} when none runs)."""
    from turtlectl.runtime.client.session import client_session, live_graph
    from turtlectl.runtime.client.typebook import descriptions

    try:
        with client_session(connect, domain) as session:
            return descriptions(session), keys_by_type(live_graph(session, domain))
    except Unreachable:
        return {}, {}


def is_builtin(name: str) -> bool:
    """Whether ``name`` is a built-in's full name (a short one may also be a running node's type)."""
    return any(type_name(t).lower() == name.lower() for t in ALL_TYPES)


def listing(live: Live | None = None, keys: Keys | None = None) -> list[dict[str, Any]]:
    """Every message type: its name, the keys that carry it, and its summary; then the types
    the running nodes use besides (``live``), with those nodes, any conflict and the keys that
    carry them in the live graph (``keys``)."""
    rows = [{"type": type_name(t), "keys": _keys_of(t), "summary": summary(t)} for t in ALL_TYPES]
    builtin = {r["type"] for r in rows}
    for name, said in sorted((live or {}).items()):
        if name in builtin:
            continue
        first = next(iter(said.values()))
        row = {"type": name, "keys": (keys or {}).get(name, []), "summary": first.doc, "nodes": sorted(said)}
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


def description(name: str, live: Live | None = None, keys: Keys | None = None) -> dict[str, Any]:
    """One type in full: wire tag and encoding, the keys that carry it, its documentation and
    every field (type, default, unit, range, meaning).  A type the running nodes use (``live``)
    from its description, its keys from the live graph (``keys``); a Struct nested in one from
    its definition.  A short name means a type the running system's keys carry, where one does,
    before any other known type.  BadInput naming the built-ins and the live types for a name
    that is no type."""
    builtins = {type_name(t): t for t in ALL_TYPES}
    # a short name means a type the running system's keys carry first (a student's TurtleStatus where
    # turtlectl's is not in use), else any known one; BadInput: a short name several such types have
    in_use = [t for t in keys or {} if t in builtins or t in (live or {})]
    full = which_type(name, in_use) or which_type(name, [*builtins, *(live or {})])
    builtin = builtins.get(full or "")
    if builtin is None and full is not None and live:
        return live_description(live[full], (keys or {}).get(full, []), conflict(live[full]))
    if builtin is None:
        nested = nested_description(name, live or {})
        if nested is None:
            raise BadInput(f"unknown message type {name!r} (known: {', '.join(_known(live or {}))}; {_SHOW_HINT})")
        return nested
    tag = type_name(builtin)
    fields = []
    for f in struct_fields(builtin):
        unit, span, meaning = FIELDS[type_short_name(builtin)][f.name]
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
        "encoding": encoding_for(builtin),
        "keys": _keys_of(builtin),
        "doc": doc(builtin),
        "fields": fields,
    }


_SHOW_HINT = "`turtlectl interface show TYPE` for fields"


def _known(live: Live) -> list[str]:
    """The built-in types' names, then the live ones'."""
    builtins = sorted(type_name(t) for t in ALL_TYPES)
    return builtins + sorted(n for n in live if n not in builtins)


def description_text(d: dict[str, Any]) -> str:
    if d.get("nested_in"):
        first = f"{d['type']}: {d['what']} nested in {', '.join(d['nested_in'])} (no type tag: never sent alone)"
    else:
        first = f'{d["type"]}: msgpack map tagged "type": "{d["type"]}" (encoding {d["encoding"]})'
    head = [first, f"keys: {', '.join(d['keys']) or '(none of its own)'}"]
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
    meanings = [f"  {f['name']}: {f['meaning']}" for f in d["fields"] if f["meaning"]]  # a nested Struct's: none
    tail = ["", "meaning:", *meanings] if meanings else [] if d["fields"] else ["(no fields)"]
    return "\n".join(head + table + tail)
