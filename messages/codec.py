"""Encoding and decoding of wire messages: msgpack via msgspec.

Every sample carries an encoding string ``application/msgpack;<package/Name>`` (the type's full
name, messages.naming) so a generic tool
(``turtlectl echo``) can decode any topic without knowing it in advance.  The types known by
name are the built-ins and every type this process has used (``register``: a node registers
the types it declares, a tool the ones it learnt from their descriptions); a decoder is built
for a type on first use, and every failure to decode is ``DecodeError`` (a ValueError).
"""

from __future__ import annotations

from typing import TypeVar, Union

import msgspec

from turtlectl.messages.naming import REBUILT, lookup, short_name
from turtlectl.messages.types import ALL_TYPES, Message

MEDIA_TYPE = "application/msgpack"

M = TypeVar("M", bound=Message)


def type_name(msg_type: type[Message]) -> str:
    """The full name a message type travels under, ``package/Name`` (its wire tag, never the
    class name): ``turtlectl/Pose``, ``capstone_msgs/TurtleStatus``."""
    return str(msg_type.__struct_config__.tag)


def type_short_name(msg_type: type[Message]) -> str:
    """The name without its package: ``TurtleStatus`` for ``capstone_msgs/TurtleStatus``."""
    return short_name(type_name(msg_type))


def shown_name(msg_type: object) -> str:
    """How people are told of a type: a message type's full name, another class's own name."""
    if isinstance(msg_type, type) and issubclass(msg_type, Message):
        return type_name(msg_type)
    return str(getattr(msg_type, "__name__", msg_type))


TYPES_BY_NAME: dict[str, type[Message]] = {type_name(t): t for t in ALL_TYPES}

_encoder = msgspec.msgpack.Encoder()
_decoders: dict[type, msgspec.msgpack.Decoder] = {}
_any_decoder: list[msgspec.msgpack.Decoder] = []  # of every known type, made again when one is added


class TypeClash(ValueError):
    """Two different classes under one full name in one process: neither can be told apart on the wire."""


class DecodeError(ValueError):
    """A payload that is not a valid message of the expected type."""


def encode(msg: Message) -> bytes:
    """Serialise a message to msgpack bytes (its type name travels as the tag)."""
    return _encoder.encode(msg)


def encoding_for(msg_type: type[Message]) -> str:
    """The sample encoding string that names ``msg_type``, e.g. ``application/msgpack;turtlectl/Pose``."""
    return f"{MEDIA_TYPE};{type_name(msg_type)}"


def register(msg_type: type[Message]) -> type[Message]:
    """Know ``msg_type`` by its name from now on (``type_from_encoding``, ``decode_any``).
    A class of the user's own takes the place of one a tool rebuilt from the wire under its
    name (a script that learnt ``WallState`` through the client, then uses its own); otherwise
    TypeClash if another class already goes by that name in this process."""
    name = type_name(msg_type)
    known = TYPES_BY_NAME.setdefault(name, msg_type)
    if known is not msg_type and getattr(known, REBUILT, False) and not getattr(msg_type, REBUILT, False):
        TYPES_BY_NAME[name] = known = msg_type
    if known is not msg_type:
        raise TypeClash(
            f"two message types named {name!r}: {known.__module__}.{known.__qualname__} and "
            f"{msg_type.__module__}.{msg_type.__qualname__}"
        )
    _any_decoder.clear()
    return msg_type


def named(name: str) -> type[Message] | None:
    """The known type a user's ``name`` means: a full name, or a short name only one known type
    has (messages.naming.lookup); None for none; AmbiguousType when several have it."""
    found = lookup(name, TYPES_BY_NAME)
    return None if found is None else TYPES_BY_NAME[found]


def decode(payload: bytes, msg_type: type[M]) -> M:
    """Decode ``payload`` as ``msg_type``; raise DecodeError with a readable reason."""
    decoder = _decoders.get(msg_type)
    try:
        if decoder is None:
            decoder = _decoders[msg_type] = msgspec.msgpack.Decoder(msg_type)
        return decoder.decode(payload)
    except (msgspec.DecodeError, TypeError) as exc:  # ValidationError is a DecodeError; TypeError: not a type
        raise DecodeError(f"not a valid {shown_name(msg_type)}: {exc}") from None


def decode_any(payload: bytes) -> Message:
    """Decode a payload of any known type, using its tag."""
    if not _any_decoder:
        _any_decoder.append(msgspec.msgpack.Decoder(Union[tuple(TYPES_BY_NAME.values())]))  # type: ignore[misc]  # noqa: UP007
    try:
        return _any_decoder[0].decode(payload)
    except msgspec.DecodeError as exc:
        raise DecodeError(f"not a valid turtlectl message: {exc}") from None


def type_from_encoding(encoding: str) -> type[Message] | None:
    """The message type named by a sample encoding string, or None if unknown."""
    media, _, schema = encoding.partition(";")
    if media != MEDIA_TYPE:
        return None
    return TYPES_BY_NAME.get(schema)


def to_builtins(msg: Message) -> dict:
    """The message as plain Python data (with its ``type`` tag), for printing."""
    return msgspec.to_builtins(msg)


def to_json(msg: Message) -> bytes:
    """One-line JSON of a message, ``inf``/``NaN`` spelled ``"Infinity"``, ``"-Infinity"``,
    ``"NaN"`` (JSON has none): the one rule of every JSON turtlectl writes (messages.jsonform)."""
    from turtlectl.messages.jsonform import to_json as spelled_json  # jsonform builds on this module

    return spelled_json(msg)
