"""The turtlectl wire contract: message types, codec and key expressions."""

from messages.codec import (
    DecodeError,
    decode,
    decode_any,
    encode,
    encoding_for,
    to_builtins,
    to_json,
    type_from_encoding,
)
from messages.types import (
    ALL_TYPES,
    ErrorReply,
    LaserScan,
    Message,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    TurtleStatus,
    Twist,
)

__all__ = [
    "ALL_TYPES",
    "DecodeError",
    "ErrorReply",
    "LaserScan",
    "Message",
    "NavigateToRequest",
    "NavigateToResponse",
    "Pose",
    "TurtleStatus",
    "Twist",
    "decode",
    "decode_any",
    "encode",
    "encoding_for",
    "to_builtins",
    "to_json",
    "type_from_encoding",
]
