"""Message types described on the wire (pure: no zenoh): what a tool needs to understand a type
it was not built with, as ROS 2's type descriptions (REP 2011) but with no build step.

A description (``TypeDescription``) is made from the class alone: its name (the wire tag), its
JSON Schema (msgspec's), its fields in order with their unit and meaning (a built-in's from
``messages.reference``, a user type's from the ``# unit: meaning`` comment after each field),
its docstring's first paragraph, and a hash of the name and schema, so two different types
under one name are told apart.  ``struct_from`` makes a class back from a description: a tool
decodes, validates and encodes with it as with the original.

Supported field types (what a description can carry and ``struct_from`` rebuilds): bool, int,
float, str, bytes, enums (of str or int values), nested Structs, lists, tuples, dicts with
str keys, and ``X | None``; defaults that JSON can write (a NaN or infinite default is
described as none: the field becomes required in the rebuilt class).
"""

from __future__ import annotations

import enum
from typing import Any, Union

import msgspec

from turtlectl.messages.naming import REBUILT, is_full, short_name
from turtlectl.messages.types import ALL_TYPES, Message

HASH_PREFIX = "TH01_"  # a type hash: version 1 of this scheme, then sha256 of name and schema


class FieldDescription(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """One field of a described type, in the type's order: its name on the wire, its JSON
    Schema type (a nested Struct's or an enum's name for those), its unit and meaning."""

    name: str
    type: str  # as JSON Schema names it: "number", "integer", "string", "array", ... or a Struct's name
    unit: str = ""
    meaning: str = ""


class TypeDescription(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """What ``turtlectl/types/<name>/<node>`` answers (JSON): one message type as a node uses it."""

    name: str
    hash: str
    doc: str
    fields: list[FieldDescription]
    schema: dict[str, Any]  # the JSON Schema of one message, with its nested Structs in $defs


def describable(name: str) -> bool:
    """Whether a type could be described under ``name`` (``turtlectl/types/<package.Name>/<node>``):
    a full name, ``package/Name``.  A raw payload's encoding may name anything (``a//b``, ``**``)."""
    return is_full(name)


def type_hash(name: str, schema: dict[str, Any]) -> str:
    """``TH01_`` and the sha256 of the name and the canonical JSON of the schema."""
    import hashlib  # here: a node imports this module at start, and describes a type only when asked

    canonical = msgspec.json.encode({"name": name, "schema": schema}, order="sorted")
    return HASH_PREFIX + hashlib.sha256(canonical).hexdigest()


def field_comments(cls: type) -> dict[str, str]:
    """``# comments`` after the fields in the class's source: a message type's and a parameter
    Struct's ``unit: meaning``.  A class without source (defined in ``python -c``, or shipped
    without its .py) has none: its fields are described without them."""
    import inspect  # here: ~10 ms that a node's start does not pay (it describes only when asked)

    try:
        source = inspect.getsource(cls)
    except (OSError, TypeError):
        return {}
    found: dict[str, str] = {}
    for line in source.splitlines():
        name, colon, rest = line.strip().partition(":")
        if colon and name.isidentifier() and "#" in rest:
            found[name] = rest.split("#", 1)[1].strip()
    return found


def _unit_meaning(cls: type[Message], field: str, comments: dict[str, str]) -> tuple[str, str]:
    if cls in ALL_TYPES:
        from turtlectl.messages.reference import FIELDS

        unit, _, meaning = FIELDS.get(short_name(str(cls.__struct_config__.tag)), {}).get(field, ("", "", ""))  # type: ignore[arg-type]
        return unit, meaning
    unit, colon, meaning = comments.get(field, "").partition(":")
    return (unit.strip(), meaning.strip()) if colon else ("", unit.strip())


def _schema_type(prop: dict[str, Any]) -> str:
    if "$ref" in prop:
        return prop["$ref"].rsplit("/", 1)[-1]
    if "anyOf" in prop:
        return " | ".join(_schema_type(p) for p in prop["anyOf"])
    if "enum" in prop:
        return "enum"
    return str(prop.get("type", "any"))


def describe(cls: type[Message]) -> TypeDescription:
    """The description of message type ``cls``."""
    name = str(cls.__struct_config__.tag)
    schema = msgspec.json.schema(cls)
    body = schema["$defs"][schema["$ref"].rsplit("/", 1)[-1]]
    comments = {} if cls in ALL_TYPES else field_comments(cls)
    fields = []
    for field in msgspec.structs.fields(cls):
        unit, meaning = _unit_meaning(cls, field.name, comments)
        prop = body.get("properties", {}).get(field.encode_name, {})
        fields.append(FieldDescription(field.encode_name, _schema_type(prop), unit, meaning))
    import inspect

    doc = inspect.cleandoc(cls.__doc__ or "").split("\n\n")[0].replace("\n", " ")
    return TypeDescription(name=name, hash=type_hash(name, schema), doc=doc, fields=fields, schema=schema)


# -- a class from a description -------------------------------------------------------------
_SCALARS: dict[str, Any] = {"number": float, "integer": int, "string": str, "boolean": bool, "null": type(None)}


class DescriptionError(ValueError):
    """A description that cannot be made into a class (a schema outside what is supported)."""


def struct_from(description: TypeDescription) -> type[Message]:
    """A message class equivalent to the one ``description`` describes: same name, fields,
    types, constraints' kinds and defaults; DescriptionError for what is not supported."""
    schema = description.schema
    defs: dict[str, Any] = schema.get("$defs", {})
    made: dict[str, Any] = {}
    root = schema["$ref"].rsplit("/", 1)[-1]

    def of(prop: dict[str, Any]) -> Any:
        if "$ref" in prop:
            return struct(prop["$ref"].rsplit("/", 1)[-1])
        if "anyOf" in prop:
            return Union[tuple(of(p) for p in prop["anyOf"])]  # type: ignore[misc]  # noqa: UP007
        if "enum" in prop:
            values = prop["enum"]
            return enum.Enum(prop.get("title", "Choice"), {str(v).upper() or "EMPTY": v for v in values})
        kind = prop.get("type")
        if kind == "string" and prop.get("contentEncoding") == "base64":
            return bytes
        if kind in _SCALARS:
            return _SCALARS[kind]
        if kind == "array":
            if "prefixItems" in prop:
                return tuple[tuple(of(p) for p in prop["prefixItems"])]  # type: ignore[misc]
            return list[of(prop.get("items", {}))] if prop.get("items") else list  # type: ignore[misc]
        if kind == "object":
            return dict[str, of(prop["additionalProperties"])] if prop.get("additionalProperties") else dict  # type: ignore[misc]
        if not {k: v for k, v in prop.items() if k not in ("default", "title", "description")}:
            return Any  # an untyped field (Any): msgspec's schema names no type
        raise DescriptionError(f"{description.name}: a field of JSON Schema {prop} is not supported")

    def struct(name: str) -> Any:
        if name in made:
            return made[name]
        body = defs.get(name)
        if body is None:
            raise DescriptionError(f"{description.name}: no definition of {name}")
        if "enum" in body:  # an Enum class: msgspec puts it in $defs
            made[name] = of({**body, "title": name})
            return made[name]
        required = set(body.get("required", ()))
        tag_field = body.get("properties", {}).get("type", {})
        fields = []
        for key, prop in body.get("properties", {}).items():
            if name == root and key == "type" and "enum" in tag_field:
                continue  # the tag field: Message's own
            if key in required:
                fields.append((key, of(prop)))
            elif "default" in prop:
                kind = of(prop)
                fields.append((key, kind, _default(_as(prop["default"], kind))))
            else:
                fields.append((key, Union[of(prop), None], None))  # noqa: UP007
        if name == root:
            made[name] = _message_class(name, fields, description.name)  # the user's own class may take its place
        else:
            made[name] = msgspec.defstruct(name, fields, kw_only=True, frozen=True)
        return made[name]

    return struct(root)


def _message_class(name: str, fields: list[tuple[Any, ...]], tag: str) -> type[Message]:
    """A Message subclass with ``fields`` (as msgspec.defstruct takes them) and the full name
    ``tag``, as it is: made through Message's own metaclass (defstruct does not take a subclass of it)."""
    namespace: dict[str, Any] = {"__module__": __name__, REBUILT: True, "__annotations__": {f[0]: f[1] for f in fields}}
    namespace.update({f[0]: f[2] for f in fields if len(f) == 3})
    return type(Message)(name, (Message,), namespace, tag=tag, kw_only=True)  # type: ignore[no-any-return]


def _as(value: Any, kind: Any) -> Any:
    """A default as JSON wrote it, as the field holds it: bytes from base64, an enum member, a
    tuple, a Struct (kept as written if it does not convert)."""
    try:
        return msgspec.json.decode(msgspec.json.encode(value), type=kind)
    except (msgspec.DecodeError, TypeError):
        return value


def _default(value: Any) -> Any:
    """A default as a field can hold it: a fresh copy for lists and dicts (msgspec copies
    empty ones; a factory for the rest)."""
    if isinstance(value, list | dict) and value:
        return msgspec.field(default_factory=lambda: msgspec.json.decode(msgspec.json.encode(value)))
    return value
