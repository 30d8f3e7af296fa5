"""Messages and parameters built from what a user types (pure: no zenoh).

Everything is validated before anything is sent or started; errors are
BadInput naming the field.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import msgspec

from turtlectl.cli.system.launchfile import validation_parts
from turtlectl.messages import Message
from turtlectl.messages.codec import TYPES_BY_NAME
from turtlectl.messages.codec import type_name as name_of
from turtlectl.messages.keys import TOPICS, service_types
from turtlectl.messages.naming import AmbiguousType, lookup
from turtlectl.runtime.client.errors import BadInput


def _problem(exc: msgspec.ValidationError) -> str:
    what, path = validation_parts(exc)
    path = path.lstrip(".")
    return f"{path}: {what}" if path else what


def which_type(name: str, known: Iterable[str]) -> str | None:
    """The full name among ``known`` that a name a user typed means: a full name (any case), or
    a short name only one known type has; None for none.  BadInput naming the full names to
    choose from for a short name several types have (``TurtleStatus``: turtlectl's and a user's)."""
    try:
        return lookup(name, known)
    except AmbiguousType as exc:
        raise BadInput(str(exc)) from None


def type_named(name: str) -> type[Message]:
    """The message type called ``name`` (full, or short where unambiguous; any case); BadInput
    naming the known ones otherwise."""
    full = which_type(name, TYPES_BY_NAME)
    found = None if full is None else TYPES_BY_NAME[full]
    if found is None:
        names = ", ".join(sorted(TYPES_BY_NAME))
        raise BadInput(f"unknown message type {name!r} (known: {names}; `turtlectl interface show TYPE` for fields)")
    return found


def message_type(key: str, type_name: str | None, table: dict[str, Any], verb: str = "carries") -> type[Message]:
    """The message type for ``key``: the one ``table`` declares (a known key keeps its own
    type: ``--type`` naming another is refused, "KEY <verb> Twist, not Pose"), else ``type_name``."""
    entry = table.get(key)
    known = None if entry is None else (entry[0] if isinstance(entry, tuple) else entry)
    if type_name is not None:
        found = type_named(type_name)
        if known is not None and found is not known:
            raise BadInput(f"{key} {verb} {name_of(known)}, not {name_of(found)}")
        return found
    if known is None:
        raise BadInput(f"no known message type for {key!r}: give one with --type")
    return known


def message_from_json(text: str, msg_type: type[Message]) -> Message:
    """``msg_type`` from JSON text (the ``type`` tag may be left out)."""
    try:
        return msgspec.json.decode(text.encode(), type=msg_type)
    except msgspec.ValidationError as exc:
        raise BadInput(f"not a valid {name_of(msg_type)}: {_problem(exc)}") from None
    except msgspec.DecodeError as exc:
        raise BadInput(f"not valid JSON: {exc}") from None


def json_text(text: str) -> None:
    """BadInput if ``text`` is not JSON at all (its fields are checked against a type later)."""
    try:
        msgspec.json.decode(text.encode())
    except msgspec.DecodeError as exc:
        raise BadInput(f"not valid JSON: {exc}") from None


def topic_message(key: str, text: str, type_name: str | None = None) -> Message:
    return message_from_json(text, message_type(key, type_name, TOPICS))


def service_request(key: str, text: str, type_name: str | None = None) -> Message | bytes:
    """The request for ``key``: a typed message for a known service, else the JSON text as bytes."""
    types = service_types(key)
    if type_name is None and types is None:
        json_text(text)
        return text.encode()
    table = {} if types is None else {key: types}
    return message_from_json(text, message_type(key, type_name, table, verb="takes"))
