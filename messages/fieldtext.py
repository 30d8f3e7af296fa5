"""A Struct's fields as text for people: each field's type name and default, and a class's
docstring (``turtlectl interface``, ``param describe``, docs/gen_interfaces.py).  Pure: no zenoh."""

from __future__ import annotations

import inspect
import math

import msgspec


def type_name(t: msgspec.inspect.Type) -> str:
    if isinstance(t, msgspec.inspect.FloatType):
        return "float"
    if isinstance(t, msgspec.inspect.IntType):
        return "int"
    if isinstance(t, msgspec.inspect.BoolType):
        return "bool"
    if isinstance(t, msgspec.inspect.StrType):
        return "str"
    if isinstance(t, msgspec.inspect.EnumType) and issubclass(t.cls, str):
        return "str"  # on the wire, the value; the range column lists the values
    if isinstance(t, msgspec.inspect.ListType):
        return f"list[{type_name(t.item_type)}]"
    if isinstance(t, msgspec.inspect.StructType):
        return t.cls.__name__
    if isinstance(t, msgspec.inspect.DictType):
        return "map"
    if isinstance(t, msgspec.inspect.AnyType):
        return "any"
    return type(t).__name__.removesuffix("Type").lower()


def default_text(field: msgspec.inspect.Field) -> str:
    if field.required:
        return "required"
    value = field.default
    if value is msgspec.NODEFAULT and field.default_factory is not msgspec.NODEFAULT:
        value = field.default_factory()
    if isinstance(value, float):
        return "NaN" if math.isnan(value) else f"{value:.8g}"
    if isinstance(value, msgspec.Struct):
        return "(table)"
    return msgspec.json.encode(value).decode()


def doc(cls: type) -> str:
    return inspect.cleandoc(cls.__doc__ or "").strip()


def struct_fields(cls: type) -> list[msgspec.inspect.Field]:
    return list(msgspec.inspect.type_info(cls).fields)
