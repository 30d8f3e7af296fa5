"""Encoding and decoding of wire messages: msgpack via msgspec.

Encoders and decoders are built once at import.  Every sample also carries an
encoding string ``application/msgpack;<TypeName>`` so a generic tool (``turtlectl
echo``) can decode any topic without knowing it in advance.
"""

from __future__ import annotations

from typing import TypeVar, Union

import msgspec

from turtlectl.messages.types import ALL_TYPES, Message

MEDIA_TYPE = "application/msgpack"

M = TypeVar("M", bound=Message)


def type_name(msg_type: type[Message]) -> str:
    """The name a message type travels under: its explicit wire tag, never the class name."""
    return str(msg_type.__struct_config__.tag)


TYPES_BY_NAME: dict[str, type[Message]] = {type_name(t): t for t in ALL_TYPES}

_encoder = msgspec.msgpack.Encoder()
_decoders: dict[type[Message], msgspec.msgpack.Decoder] = {t: msgspec.msgpack.Decoder(t) for t in ALL_TYPES}
_any_decoder = msgspec.msgpack.Decoder(Union[ALL_TYPES])  # type: ignore[valid-type]  # noqa: UP007 (a tuple of types)


class DecodeError(ValueError):
    """A payload that is not a valid message of the expected type."""


def encode(msg: Message) -> bytes:
    """Serialise a message to msgpack bytes (its type name travels as the tag)."""
    return _encoder.encode(msg)


def encoding_for(msg_type: type[Message]) -> str:
    """The sample encoding string that names ``msg_type``, e.g. ``application/msgpack;Pose``."""
    return f"{MEDIA_TYPE};{type_name(msg_type)}"


def decode(payload: bytes, msg_type: type[M]) -> M:
    """Decode ``payload`` as ``msg_type``; raise DecodeError with a readable reason."""
    try:
        return _decoders[msg_type].decode(payload)
    except msgspec.DecodeError as exc:  # ValidationError is a subclass
        raise DecodeError(f"not a valid {msg_type.__name__}: {exc}") from None


def decode_any(payload: bytes) -> Message:
    """Decode a payload of any known type, using its tag."""
    try:
        return _any_decoder.decode(payload)
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
