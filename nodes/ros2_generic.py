"""A user's own flat message type as a ROS 2 type: its ``.msg`` text and its fields, generically.

Pure: no network, no ROS library.  A type ``capstone_msgs/Status`` (turtlectl's full name) is
``capstone_msgs/msg/Status`` in ROS; each field keeps its name, in declaration order: ``float`` is
``float64``, ``int`` ``int64``, ``bool`` ``bool``, ``str`` ``string``, a list of one of those a sequence
(``float64[]``), a tuple of one of those a fixed array (``float64[3]``).  A type with any other field
(a nested Struct, an enum, a dict, an optional) has no generic ROS type: ``msg_text`` gives None,
``field_that_cannot_cross`` names the field.

``user_type`` finds a user's type by its ROS name (the ROS 2 bridge's rows): ``my_msgs/msg/Reading`` is
turtlectl's ``my_msgs/Reading``, a class already known in this process or declared in the module its
package names (``my_msgs.py`` or ``my_msgs/``, imported from the launch file's folder, the working
folder or ``PYTHONPATH``).
"""

from __future__ import annotations

import importlib
import os
import re
import sys
from pathlib import Path
from typing import Any

import msgspec

from turtlectl.messages import Message
from turtlectl.messages.codec import TYPES_BY_NAME, type_name
from turtlectl.messages.naming import REBUILT
from turtlectl.runtime.config import PROJECT_VAR

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


def turtlectl_name(ros_type: str) -> str | None:
    """A ROS 2 type name ``pkg/msg/Name`` as turtlectl's full name ``pkg/Name`` (None: not a message type)."""
    parts = ros_type.split("/")
    if len(parts) != 3 or parts[1] != "msg" or not all(p.isidentifier() for p in parts):
        return None
    return f"{parts[0]}/{parts[2]}"


def _declared(name: str) -> type[Message] | None:
    known = TYPES_BY_NAME.get(name)
    if known is not None and not getattr(known, REBUILT, False):
        return known
    todo = list(Message.__subclasses__())
    while todo:
        cls = todo.pop()
        todo.extend(cls.__subclasses__())
        if not getattr(cls, REBUILT, False) and type_name(cls) == name:
            return cls
    return None


def user_type(ros_type: str) -> type[Message] | None:
    """The user's own message class of ROS 2 type ``ros_type`` (``my_msgs/msg/Reading``): one declared
    in this process already, else in the module of its package (imported now from sys.path, the launch
    file's folder (PROJECT_VAR) or the working folder); None when there is none (or the module does not import).  turtlectl's own
    package (``turtlectl``) is never a user's."""
    name = turtlectl_name(ros_type)
    if name is None or name.startswith("turtlectl/"):
        return None
    found = _declared(name)
    if found is not None:
        return found
    for folder in (os.environ.get(PROJECT_VAR), str(Path.cwd())):  # the launch file's, the working one
        if folder and folder not in sys.path:
            sys.path.append(folder)
    try:
        importlib.import_module(name.split("/")[0])
    except Exception:  # no such module, or one that does not import: no such type here
        return None
    return _declared(name)


def field_that_cannot_cross(cls: type[msgspec.Struct]) -> str | None:
    """``name: type`` of the first field of ``cls`` that has no generic ROS type, or None (flat)."""
    declared = {f.name: f.type for f in msgspec.structs.fields(cls)}
    for f in msgspec.inspect.type_info(cls).fields:
        if _field(f.type) is None:
            kind = declared.get(f.name)
            shown = kind.__name__ if isinstance(kind, type) else re.sub(r"\b(?:\w+\.)+(\w+)", r"\1", str(kind))
            return f"{f.name}: {shown}"
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
