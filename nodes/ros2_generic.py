"""A user's own flat message type as a ROS 2 type: its ``.msg`` text and its fields, generically.

Pure: no network, no ROS library.  A type ``capstone_msgs/Status`` (turtlectl's full name) is
``capstone_msgs/msg/Status`` in ROS; each field keeps its name, in declaration order: ``float`` is
``float64``, ``int`` ``int64``, ``bool`` ``bool``, ``str`` ``string``, a list of one of those a sequence
(``float64[]``), a tuple of one of those a fixed array (``float64[3]``).  A type with any other field
(a nested Struct, an enum, a dict, an optional) has no generic ROS type: ``msg_text`` gives None.
"""

from __future__ import annotations

from typing import Any

import msgspec

_BASE = {
    msgspec.inspect.FloatType: "float64",
    msgspec.inspect.IntType: "int64",
    msgspec.inspect.BoolType: "bool",
    msgspec.inspect.StrType: "string",
}


def ros_name(full_name: str) -> str:
    """turtlectl's full name ``pkg/Name`` as a ROS 2 type name ``pkg/msg/Name``."""
    package, _, name = full_name.rpartition("/")
    return f"{package}/msg/{name}"


def _field(info: Any) -> str | None:
    base = _BASE.get(type(info))
    if base is not None:
        return base
    if isinstance(info, msgspec.inspect.ListType):
        item = _BASE.get(type(info.item_type))
        return None if item is None else f"{item}[]"
    if isinstance(info, msgspec.inspect.TupleType) and info.item_types:
        items = {_BASE.get(type(t)) for t in info.item_types}
        item = items.pop() if len(items) == 1 else None
        return None if item is None else f"{item}[{len(info.item_types)}]"
    return None


def msg_text(cls: type[msgspec.Struct]) -> str | None:
    """The ``.msg`` text of a flat message class (one ``type name`` line per field), or None."""
    lines = []
    for f in msgspec.inspect.type_info(cls).fields:
        kind = _field(f.type)
        if kind is None:
            return None
        lines.append(f"{kind} {f.name}")
    return "\n".join(lines) + "\n"


def fields_of(message: msgspec.Struct) -> dict[str, Any]:
    """A flat message's fields, by name (tuples as lists)."""
    return {
        name: list(value) if isinstance(value, tuple) else value
        for name, value in msgspec.structs.asdict(message).items()
    }
