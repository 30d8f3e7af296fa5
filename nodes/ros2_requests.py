"""ROS 2 service requests, the pure part: which service types turtlectl can call over DDS, their
fields, the DDS names a Fast DDS server matches, and the request a user types.

* :data:`SERVICE_TYPES` is the one table of the service types: for each ROS name
  (``std_srvs/srv/SetBool``) the request's and the response's fields in ``.srv`` order, each with its
  ``.srv`` type (``bool``, ``string``, ``float32``, ``uint8``, ...).  A ``.srv`` side with no field
  has one ``uint8 structure_needs_at_least_one_member`` on the wire, as ROS's IDL generator adds.
* :func:`service_topics` names the two DDS topics of a ROS service (``rq/<name>Request`` the client
  writes, ``rr/<name>Reply`` it reads), :func:`request_type_name` / :func:`response_type_name` the
  DDS types (``std_srvs::srv::dds_::SetBool_Request_``).
* :func:`parse_request` reads the request as ``ros2 service call`` takes it, a YAML flow mapping
  (``{data: true}``, ``"{x: 1.5, name: 'a b'}"``) or JSON; :func:`fit_request` checks it against the
  type and fills the fields not given with their defaults (``false``, ``0``, ``""``).

Errors are ``ValueError`` with one line saying what is wrong.  No DDS here (``ros2_services`` is the
DDS side): this module imports nothing beyond the standard library.
"""

from __future__ import annotations

import json
import math
import re
from typing import Any

#: the field a .srv side without fields has on the wire (ROS's IDL generator adds it)
PLACEHOLDER = "structure_needs_at_least_one_member"

#: ranges of the ROS integer types
INT_RANGES: dict[str, tuple[int, int]] = {
    "byte": (0, 255),
    "char": (0, 255),
    "uint8": (0, 255),
    "int8": (-128, 127),
    "uint16": (0, 65535),
    "int16": (-32768, 32767),
    "uint32": (0, 2**32 - 1),
    "int32": (-(2**31), 2**31 - 1),
    "uint64": (0, 2**64 - 1),
    "int64": (-(2**63), 2**63 - 1),
}
FLOATS = ("float32", "float64")
PRIMITIVES = ("bool", "string", *FLOATS, *INT_RANGES)

Fields = tuple[tuple[str, str], ...]

#: ROS service type -> (request fields, response fields), each (name, .srv type) in .srv order
SERVICE_TYPES: dict[str, tuple[Fields, Fields]] = {
    "std_srvs/srv/Empty": ((), ()),
    "std_srvs/srv/SetBool": ((("data", "bool"),), (("success", "bool"), ("message", "string"))),
    "std_srvs/srv/Trigger": ((), (("success", "bool"), ("message", "string"))),
    "turtlesim/srv/Spawn": (
        (("x", "float32"), ("y", "float32"), ("theta", "float32"), ("name", "string")),
        (("name", "string"),),
    ),
    "turtlesim/srv/Kill": ((("name", "string"),), ()),
    "turtlesim/srv/TeleportAbsolute": ((("x", "float32"), ("y", "float32"), ("theta", "float32")), ()),
    "turtlesim/srv/TeleportRelative": ((("linear", "float32"), ("angular", "float32")), ()),
    "turtlesim/srv/SetPen": (
        (("r", "uint8"), ("g", "uint8"), ("b", "uint8"), ("width", "uint8"), ("off", "uint8")),
        (),
    ),
}


def check_service_type(ros_type: str) -> tuple[Fields, Fields]:
    """The request and response fields of ``ros_type``; ValueError naming the known types if it is
    not one of :data:`SERVICE_TYPES`."""
    if ros_type not in SERVICE_TYPES:
        known = ", ".join(sorted(SERVICE_TYPES))
        raise ValueError(f"unknown service type {ros_type!r} (known: {known})")
    return SERVICE_TYPES[ros_type]


def wire_fields(fields: Fields) -> Fields:
    """The fields as they are on the wire: a side without fields has the one placeholder byte."""
    return fields or ((PLACEHOLDER, "uint8"),)


def check_service_name(name: str) -> str:
    """A ROS service name, absolute (``set_flag`` -> ``/set_flag``); ValueError if it is not one
    (ROS names: letters, digits, ``_`` and ``/`` separators, no empty part, not starting with a digit)."""
    absolute = "/" + name.lstrip("/") if not name.startswith("/") else name
    if not re.fullmatch(r"(/[A-Za-z_][A-Za-z0-9_]*)+", absolute):
        raise ValueError(f"{name!r} is no ROS service name (as /set_flag or /turtle1/teleport_absolute)")
    return absolute


def service_topics(service: str) -> tuple[str, str]:
    """The DDS topics of a ROS service: the request's (the client writes) and the reply's
    (``/set_flag`` -> ``rq/set_flagRequest``, ``rr/set_flagReply``)."""
    bare = check_service_name(service).lstrip("/")
    return f"rq/{bare}Request", f"rr/{bare}Reply"


def _dds_name(ros_type: str, side: str) -> str:
    package, kind, name = ros_type.split("/")
    return f"{package}::{kind}::dds_::{name}_{side}_"


def request_type_name(ros_type: str) -> str:
    """``std_srvs/srv/SetBool`` -> ``std_srvs::srv::dds_::SetBool_Request_``."""
    return _dds_name(ros_type, "Request")


def response_type_name(ros_type: str) -> str:
    """``std_srvs/srv/SetBool`` -> ``std_srvs::srv::dds_::SetBool_Response_``."""
    return _dds_name(ros_type, "Response")


def _split_top(text: str) -> list[str]:
    """``text`` split at the commas outside quotes and brackets."""
    parts, depth, quote, start = [], 0, "", 0
    for i, char in enumerate(text):
        if quote:
            quote = "" if char == quote else quote
        elif char in "'\"":
            quote = char
        elif char in "[{":
            depth += 1
        elif char in "]}":
            depth -= 1
        elif char == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [part.strip() for part in parts if part.strip()]


def _scalar(text: str) -> Any:
    """A YAML scalar: true/false, a number, a quoted or a bare string."""
    if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
        return text[1:-1]
    lowered = text.lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    if lowered in (".inf", "+.inf", "-.inf", ".nan"):
        return float(lowered.replace(".", ""))
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def parse_request(text: str) -> dict[str, Any]:
    """The request's fields from ``text``: JSON (``{"data": true}``) or a YAML flow mapping as
    ``ros2 service call`` takes it (``{data: true}``, ``data: true``, ``{x: 1, name: 'a'}``);
    empty text is ``{}``.  ValueError if it is neither."""
    text = text.strip()
    if not text:
        return {}
    try:
        value = json.loads(text)
    except ValueError:
        value = None
    else:
        if not isinstance(value, dict):
            raise ValueError(f"the request {text!r} is no mapping of fields (as '{{data: true}}')")
        return value
    body = text[1:-1] if text.startswith("{") and text.endswith("}") else text
    fields: dict[str, Any] = {}
    for part in _split_top(body):
        name, colon, raw = part.partition(":")
        name = name.strip().strip("'\"")
        if not colon or not name or raw.strip().startswith(("{", "[")):
            raise ValueError(f"cannot read the request {text!r}: give 'field: value' pairs, as '{{data: true}}'")
        fields[name] = _scalar(raw.strip())
    return fields


def _fit_value(ros_type: str, name: str, kind: str, value: Any) -> Any:
    where = f"{ros_type} field {name!r} ({kind})"
    if kind == "bool":
        if not isinstance(value, bool):
            raise ValueError(f"{where} takes true or false, not {value!r}")
        return value
    if kind == "string":
        if not isinstance(value, str):
            raise ValueError(f"{where} takes a string, not {value!r}")
        return value
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ValueError(f"{where} takes a number, not {value!r}")
    if kind in FLOATS:
        return float(value)
    low, high = INT_RANGES[kind]
    if isinstance(value, float) and not (math.isfinite(value) and value.is_integer()):
        raise ValueError(f"{where} takes a whole number, not {value!r}")
    if not low <= value <= high:
        raise ValueError(f"{where} takes a whole number from {low} to {high}, not {value!r}")
    return int(value)


def default(kind: str) -> Any:
    """The default of a field of ``.srv`` type ``kind``: false, "", 0.0 or 0."""
    return {"bool": False, "string": ""}.get(kind, 0.0 if kind in FLOATS else 0)


def fit_request(ros_type: str, values: dict[str, Any]) -> dict[str, Any]:
    """The request of ``ros_type`` from ``values``: each field checked against its ``.srv`` type, the
    fields not given at their defaults (``false``, ``0``, ``""``), in ``.srv`` order.  ValueError on
    an unknown type, a field the type has not, or a value that does not fit."""
    request, _ = check_service_type(ros_type)
    names = [name for name, _ in request]
    for name in values:
        if name not in names:
            have = f"its fields: {', '.join(names)}" if names else "it has no fields"
            raise ValueError(f"{ros_type} has no request field {name!r} ({have})")
    return {
        name: _fit_value(ros_type, name, kind, values[name]) if name in values else default(kind)
        for name, kind in request
    }
