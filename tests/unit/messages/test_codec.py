"""Criterion 7 (unit part): every message type round-trips; malformed payloads are rejected clearly."""

import math

import msgspec
import pytest

from messages import (
    Ack,
    Cancel,
    DecodeError,
    ErrorReply,
    LaserScan,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    Reset,
    TeleportAbsolute,
    TurtleStatus,
    Twist,
    decode,
    decode_any,
    encode,
    encoding_for,
    type_from_encoding,
)

SAMPLES = [
    Twist(linear=1.5, angular=-0.25, stamp=123, seq=4),
    Pose(x=1.0, y=2.0, theta=-3.0, linear_velocity=0.5, angular_velocity=0.1, stamp=5, seq=6),
    TurtleStatus(x=1.0, y=2.0, theta=359.5, vel_x=0.1, vel_y=-0.2, battery=87.5, stamp=7, seq=8),
    LaserScan(
        angle_min=-math.pi,
        angle_max=math.pi,
        angle_increment=0.1,
        range_min=0.0,
        range_max=10.0,
        ranges=[1.0, math.inf, 2.5],
        origin_x=5.0,
        origin_y=4.0,
        origin_theta=0.5,
        stamp=9,
        seq=10,
    ),
    NavigateToRequest(x=1.0, y=2.0, theta=90.0, client="42-abcd"),
    NavigateToFeedback(
        state="driving", distance_remaining=1.5, heading_remaining=10.0, eta=0.8, elapsed=0.2, x=1, y=2, theta=3
    ),
    Cancel(),
    TeleportAbsolute(x=1.0, y=2.0, theta=0.5),
    Reset(),
    Ack(ok=False, detail="no goal is running"),
    NavigateToResponse(success=True, time_taken=1.25, position_error=0.004, heading_error=0.3, x=1, y=2, theta=90),
    ErrorReply(error="bad"),
]


@pytest.mark.parametrize("msg", SAMPLES, ids=lambda m: type(m).__name__)
def test_round_trip(msg):
    payload = encode(msg)
    assert decode(payload, type(msg)) == msg
    assert decode_any(payload) == msg
    assert type_from_encoding(encoding_for(type(msg))) is type(msg)


def test_type_name_travels_on_the_wire():
    assert msgspec.msgpack.decode(encode(Twist(linear=1.0)))["type"] == "Twist"
    assert encoding_for(TurtleStatus) == "application/msgpack;TurtleStatus"


@pytest.mark.parametrize(
    "payload, expected",
    [
        (b"\xc1garbage", "not a valid Twist"),
        (msgspec.msgpack.encode({"type": "Twist", "linear": "fast"}), "Expected `float`, got `str`"),
        (msgspec.msgpack.encode({"type": "Twist", "linear": 1.0, "boost": 2}), "unknown field `boost`"),
        (encode(Pose(x=1, y=2, theta=0)), "Invalid value 'Pose'"),
        (b"", "not a valid Twist"),
    ],
)
def test_malformed_payload_is_rejected_with_a_reason(payload, expected):
    with pytest.raises(DecodeError) as err:
        decode(payload, Twist)
    assert expected in str(err.value)


def test_missing_required_field_is_named():
    with pytest.raises(DecodeError, match="missing required field `theta`"):
        decode(msgspec.msgpack.encode({"type": "NavigateToRequest", "x": 1.0, "y": 2.0}), NavigateToRequest)


def test_unknown_encoding_names_no_type():
    assert type_from_encoding("application/json") is None
    assert type_from_encoding("application/msgpack;Nope") is None
