"""Samples as a client reads them: decoded by the type their encoding names, or learnt from the
nodes that use it (``learn``, on the reader's thread), or decoded generically when no node
describes it.  Nothing here prints or opens a session.
"""

from __future__ import annotations

from typing import Any

from turtlectl.messages import DecodeError, Message, decode, decode_any, type_from_encoding
from turtlectl.messages.codec import MEDIA_TYPE, TYPES_BY_NAME
from turtlectl.runtime.client.typebook import TypeBook, generic


class Received:
    """One sample as echo sees it: the key, the decoded message or why it is not one.  A type
    not known here keeps its payload (``unknown``: its name) for the reader's thread to learn
    it (``learn``); a payload no description explains is ``generic`` (decoded as what it is)."""

    def __init__(self, key: str, message: Message | None, problem: str = "", payload: bytes = b"", encoding: str = ""):
        self.key = key
        self.message = message
        self.problem = problem
        self.payload = payload
        self.encoding = encoding
        self.generic: Any = None  # an undescribed payload's data (dict, list, ...)

    @property
    def type_name(self) -> str:
        """The message type the sample's encoding names ('' for none)."""
        media, _, name = self.encoding.partition(";")
        return name if media == MEDIA_TYPE else ""

    @property
    def unknown(self) -> str:
        """The type name the sample's encoding gives, when no type of that name is known here."""
        name = self.type_name
        return name if self.message is None and name and name not in TYPES_BY_NAME else ""


def decode_sample(key: str, payload: bytes, encoding: str) -> Received:
    """Decode by the type named in the sample's encoding (any tagged message otherwise)."""
    msg_type = type_from_encoding(encoding)
    try:
        message = decode(payload, msg_type) if msg_type is not None else decode_any(payload)
    except DecodeError as exc:
        return Received(key, None, f"{exc} (encoding {encoding!r}, {len(payload)} bytes)", payload, encoding)
    return Received(key, message)


def learn(item: Received, book: TypeBook) -> Received:
    """``item`` again, on the reader's thread: decoded by its type learnt from the nodes that
    use it (when they describe one name two ways, by the description it fits), else (no
    description anywhere) decoded generically and marked so.  A payload that names a known
    type and is not one stays what it is: skipped, never shown as undescribed."""
    if item.message is not None:
        return item
    name = item.type_name
    if item.unknown and book.resolve(item.unknown) is not None:
        item = decode_sample(item.key, item.payload, item.encoding)
    for variant in book.variants(name) if item.message is None else ():
        try:
            return Received(item.key, decode(item.payload, variant))
        except DecodeError:
            continue
    if item.message is not None or (name and book.resolve(name) is not None):
        return item
    data = generic(item.payload, item.encoding)
    if data is not None:
        item.generic, item.problem = data, ""
    return item
