"""The one way a message is stamped as it is sent, as ROS fills a header in on publish: ``stamp``
(ns since the epoch, the sender's time) and ``seq`` (the sender's count of messages on that key,
from 0).  A node's publisher (runtime.entities), ``turtlectl pub`` and ``Client.publish`` all
stamp through ``with_stamp``.  Pure."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

import msgspec

M = TypeVar("M", bound=msgspec.Struct)


def with_stamp(message: M, now_ns: Callable[[], int], seq: int) -> M:
    """``message`` with ``stamp = now_ns()`` and ``seq``, if its type has both fields; a type
    without both (a user's need not have them) is sent as it is, and ``now_ns`` is not called."""
    fields = message.__struct_fields__
    if "stamp" in fields and "seq" in fields:
        return msgspec.structs.replace(message, stamp=now_ns(), seq=seq)
    return message
