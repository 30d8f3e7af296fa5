"""Messages as JSON, losslessly, for what reads JSON rather than msgpack: MCAP recordings that
Foxglove opens, and tools.

JSON has no infinity and no NaN (msgspec writes ``null``, which cannot be told apart on the way
back: a LaserScan's ``inf`` ranges and its ``NaN`` origin would both come back as null).  Here
a non-finite float is written as the string ``"Infinity"``, ``"-Infinity"`` or ``"NaN"``
(JavaScript's own spellings), and the JSON Schema of each type says so (``json_schema``), so
``from_json(to_json(m)) == m`` for every message, and its msgpack bytes are the original's.
One rule wherever turtlectl writes JSON: recordings, the Foxglove server, ``echo --json`` and
every other ``--json`` (cli.tools.format), the docs.
"""

from __future__ import annotations

import math
from typing import Any, Union

import msgspec

from turtlectl.messages.codec import shown_name, type_name
from turtlectl.messages.types import ALL_TYPES, Message

#: how each non-finite float is spelled in JSON here
NON_FINITE = ("Infinity", "-Infinity", "NaN")

_encoder = msgspec.json.Encoder()
_any = Union[ALL_TYPES]  # type: ignore[valid-type]  # noqa: UP007 (a tuple of types)


class JsonFormError(ValueError):
    """JSON that is not a message of a known type (or not of the type expected)."""


def spelled(value: Any) -> Any:
    """``value`` (msgspec builtins) with each non-finite float replaced by its spelling: what
    every JSON turtlectl writes goes through (recordings, the Foxglove server, ``--json``)."""
    if isinstance(value, float):
        if math.isfinite(value):
            return value
        return "NaN" if math.isnan(value) else ("Infinity" if value > 0 else "-Infinity")
    if isinstance(value, dict):
        return {k: spelled(v) for k, v in value.items()}
    if isinstance(value, list):
        return [spelled(v) for v in value]
    return value


def to_json(msg: Message) -> bytes:
    """``msg`` as one JSON object (UTF-8), its ``type`` field naming its type."""
    data = _encoder.encode(msg)
    if b"null" not in data:  # no field is None or non-finite: msgspec's bytes are already ours
        return data
    return _encoder.encode(spelled(msgspec.to_builtins(msg)))


def from_json(data: bytes, msg_type: type[Message] | None = None) -> Message:
    """The message ``to_json`` wrote: of ``msg_type``, or of the type its ``type`` field names.
    Raises JsonFormError with a readable reason."""
    try:
        obj = msgspec.json.decode(data)
        # strict=False turns the spelled non-finite floats back into floats (and only numbers'
        # strings: a str field keeps "NaN" as text)
        return msgspec.convert(obj, msg_type or _any, strict=False)
    except msgspec.DecodeError as exc:  # ValidationError included
        what = shown_name(msg_type) if msg_type is not None else "message"
        raise JsonFormError(f"not a valid {what} in JSON: {exc}") from None


def _allow_non_finite(schema: Any) -> Any:
    """Every ``{"type": "number"}`` of a msgspec JSON Schema also allows the three spellings."""
    if isinstance(schema, list):
        return [_allow_non_finite(s) for s in schema]
    if not isinstance(schema, dict):
        return schema
    out = {k: _allow_non_finite(v) for k, v in schema.items()}
    if out.get("type") == "number":
        number = {k: v for k, v in out.items() if k not in ("title", "description", "default")}
        out = {k: v for k, v in out.items() if k in ("title", "description", "default")}
        out["anyOf"] = [number, {"enum": list(NON_FINITE)}]
    return out


def _tag_optional(schema: dict[str, Any]) -> dict[str, Any]:
    """A struct's schema with its ``type`` tag optional: decoding a known type accepts it absent
    (and refuses another type's name), as requests are written (``{"x": 8, "y": 5, "theta": 90}``)."""
    tag = schema.get("properties", {}).get("type", {})
    if isinstance(tag.get("enum"), list) and len(tag["enum"]) == 1 and "type" in schema.get("required", []):
        schema = dict(schema, required=[r for r in schema["required"] if r != "type"])
    return schema


def json_schema(msg_type: type[Message]) -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of what is accepted as ``msg_type`` (``to_json``'s output
    among it): an object at the top (as Foxglove expects), titled with the type's wire name,
    nested types under ``$defs``, the ``type`` tag optional."""
    generated = msgspec.json.schema(msg_type)
    defs = {k: _tag_optional(v) for k, v in generated.get("$defs", {}).items()}
    name = generated.get("$ref", "").rpartition("/")[2]
    top = _tag_optional(dict(defs.pop(name, generated)))
    top["title"] = type_name(msg_type)
    if defs:
        top["$defs"] = defs
    top = spelled(_allow_non_finite(top))  # a NaN default too: JSON has no NaN
    top["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    return top


def _plain_numbers(schema: Any) -> Any:
    """``_allow_non_finite`` undone: each number that allows the three spellings is a number
    again (a spelled default a float again)."""
    if isinstance(schema, list):
        return [_plain_numbers(s) for s in schema]
    if not isinstance(schema, dict):
        return schema
    out = {k: _plain_numbers(v) for k, v in schema.items()}
    either = out.get("anyOf")
    if (
        isinstance(either, list)
        and len(either) == 2
        and isinstance(either[0], dict)
        and either[0].get("type") == "number"
        and either[1] == {"enum": list(NON_FINITE)}
    ):
        rest = {k: v for k, v in out.items() if k != "anyOf"}
        out = {**either[0], **rest}
        if out.get("default") in NON_FINITE:
            out["default"] = float(out["default"])
    return out


def message_class(name: str, schema: dict[str, Any]) -> type[Message]:
    """The message class ``json_schema`` described as ``name`` (a recording's schema of a type
    turtlectl was not built with), rebuilt as messages.described does from a node's description.
    DescriptionError if the schema is not one ``json_schema`` writes."""
    from turtlectl.messages.described import DescriptionError, TypeDescription, struct_from, type_hash

    if not isinstance(schema, dict) or not isinstance(schema.get("properties"), dict):
        raise DescriptionError(f"{name}: not the JSON Schema of a message")
    plain = _plain_numbers(schema)
    defs = dict(plain.pop("$defs", {}))
    short = name.rpartition("/")[2]  # a $defs key: the full name's slash would split its $ref
    root = short if short not in defs else f"{short}_"
    defs[root] = {k: v for k, v in plain.items() if k not in ("$schema", "title")} | {"title": root}
    rebuilt = {"$ref": f"#/$defs/{root}", "$defs": defs}
    description = TypeDescription(name=name, hash=type_hash(name, rebuilt), doc="", fields=[], schema=rebuilt)
    try:
        return struct_from(description)
    except (KeyError, TypeError, AttributeError) as exc:  # a schema shaped otherwise than json_schema's
        raise DescriptionError(f"{name}: not the JSON Schema of a message ({exc})") from None
