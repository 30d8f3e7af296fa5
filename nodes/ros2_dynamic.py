"""A user's own flat message type as a Cyclone DDS type, made at run time: the ROS 2 bridge's
generic rows (``type = "my_msgs/msg/Reading"``).

The struct follows nodes.ros2_generic's ``.msg`` text of the type field for field (``float`` is
float64, ``int`` int64, a list a sequence, a tuple a fixed array), named as a ROS 2 node built with
that ``.msg`` names it (``my_msgs::msg::dds_::Reading_``), keyless and final as nodes.ros2_types'
are: such a node reads what the bridge writes, and the bridge reads what it writes.

Importing this module loads the Cyclone DDS C library: only the bridge imports it, when it starts.
"""

# no `from __future__ import annotations`: cyclonedds resolves the annotations at run time

import dataclasses
import functools
import types
from typing import Any

import cyclonedds.idl.types as t
import msgspec
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.annotations import final

from turtlectl.messages import Message
from turtlectl.messages.codec import type_name
from turtlectl.nodes import ros2_generic, ros2_types

_BASE: dict[type, tuple[Any, Any]] = {  # msgspec's field kind -> (its IDL type, its default)
    msgspec.inspect.FloatType: (t.float64, 0.0),
    msgspec.inspect.IntType: (t.int64, 0),
    msgspec.inspect.BoolType: (bool, False),
    msgspec.inspect.StrType: (str, ""),
}


def _field(name: str, info: Any) -> tuple[str, Any, Any]:
    base = _BASE.get(type(info))
    if base is not None:
        return name, base[0], dataclasses.field(default=base[1])
    if isinstance(info, msgspec.inspect.ListType) and type(info.item_type) in _BASE:
        return name, t.sequence[_BASE[type(info.item_type)][0]], dataclasses.field(default_factory=list)
    if isinstance(info, msgspec.inspect.TupleType) and info.item_types:
        kinds = {type(i) for i in info.item_types}
        if len(kinds) == 1 and kinds <= set(_BASE):
            idl, default = _BASE[kinds.pop()]
            n = len(info.item_types)
            return name, t.array[idl, n], dataclasses.field(default_factory=lambda: [default] * n)
    raise ValueError(f"{name} has no ROS type")


@functools.cache
def idl_struct(cls: type[Message]) -> type:
    """The Cyclone DDS struct of a user's flat message class (ValueError for a field that cannot cross)."""
    wrong = ros2_generic.field_that_cannot_cross(cls)
    if wrong is not None:
        raise ValueError(f"{type_name(cls)}: its field {wrong} has no ROS type")
    ros_type = ros2_generic.ros_name(type_name(cls))
    fields = [_field(f.name, f.type) for f in msgspec.inspect.type_info(cls).fields]
    name = ros_type.rsplit("/", 1)[1] + "_"
    body = types.new_class(
        name,
        (IdlStruct,),
        {"typename": ros2_types.dds_type_name(ros_type)},
        lambda ns: ns.update(
            {
                "__annotations__": {n: kind for n, kind, _ in fields},
                **{n: default for n, _, default in fields},
                "__module__": __name__,
                "__doc__": f"{ros_type}, generic (nodes.ros2_generic)",
            }
        ),
    )
    return dataclasses.dataclass(final(body))


def to_ros(message: Message) -> Any:
    """A user's flat message as its Cyclone DDS struct, field for field."""
    return idl_struct(type(message))(**ros2_generic.fields_of(message))


def from_ros(sample: Any, cls: type[Message]) -> Message:
    """A sample of ``idl_struct(cls)`` as a ``cls`` message (validated: msgspec.ValidationError, a
    ValueError, for a value ``cls`` does not allow)."""
    data = {f.name: getattr(sample, f.name) for f in dataclasses.fields(sample)}
    return msgspec.convert(data, cls)
