"""Criterion 7 (unit part): every message type round-trips; malformed payloads are rejected clearly."""

import msgspec
import pytest

from tests.unit.messages.samples import SAMPLES
from turtlectl.messages import (
    DecodeError,
    NavigateToRequest,
    Pose,
    TurtleStatus,
    Twist,
    decode,
    decode_any,
    encode,
    encoding_for,
    type_from_encoding,
)


@pytest.mark.parametrize("msg", SAMPLES, ids=lambda m: type(m).__name__)
def test_round_trip(msg):
    payload = encode(msg)
    assert decode(payload, type(msg)) == msg
    assert decode_any(payload) == msg
    assert type_from_encoding(encoding_for(type(msg))) is type(msg)


def test_type_name_travels_on_the_wire():
    assert msgspec.msgpack.decode(encode(Twist(linear=1.0)))["type"] == "turtlectl/Twist"
    assert encoding_for(TurtleStatus) == "application/msgpack;turtlectl/TurtleStatus"


@pytest.mark.parametrize(
    "payload, expected",
    [
        (b"\xc1garbage", "not a valid turtlectl/Twist"),
        (msgspec.msgpack.encode({"type": "turtlectl/Twist", "linear": "fast"}), "Expected `float`, got `str`"),
        (msgspec.msgpack.encode({"type": "turtlectl/Twist", "linear": 1.0, "boost": 2}), "unknown field `boost`"),
        (encode(Pose(x=1, y=2, theta=0)), "Invalid value 'turtlectl/Pose'"),
        (b"", "not a valid turtlectl/Twist"),
    ],
)
def test_malformed_payload_is_rejected_with_a_reason(payload, expected):
    with pytest.raises(DecodeError) as err:
        decode(payload, Twist)
    assert expected in str(err.value)


def test_missing_required_field_is_named():
    with pytest.raises(DecodeError, match="missing required field `theta`"):
        decode(msgspec.msgpack.encode({"type": "turtlectl/NavigateToRequest", "x": 1.0, "y": 2.0}), NavigateToRequest)


def test_unknown_encoding_names_no_type():
    assert type_from_encoding("application/json") is None
    assert type_from_encoding("application/msgpack;Nope") is None
