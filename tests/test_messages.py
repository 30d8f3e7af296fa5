"""Criterion 7 (unit part): every message type round-trips; malformed payloads are rejected clearly."""

import inspect
import math

import msgspec
import pytest

from messages import (
    ALL_TYPES,
    Ack,
    Cancel,
    DecodeError,
    ErrorReply,
    LaserScan,
    Message,
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
from messages.angles import degrees_0_360, heading_degrees, heading_radians, wrap_radians
from messages.keys import (
    SERVICES,
    TOPICS,
    EntityInfo,
    NodeInfo,
    entity_token,
    node_token,
    parse_entity_token,
    parse_node_token,
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


def test_samples_cover_every_type():
    assert {type(m) for m in SAMPLES} == set(ALL_TYPES)


@pytest.mark.parametrize("msg", SAMPLES, ids=lambda m: type(m).__name__)
def test_round_trip(msg):
    payload = encode(msg)
    assert decode(payload, type(msg)) == msg
    assert decode_any(payload) == msg
    assert type_from_encoding(encoding_for(type(msg))) is type(msg)


def test_scan_origin_defaults_to_unknown():
    scan = LaserScan(angle_min=0, angle_max=0, angle_increment=0, range_min=0, range_max=1, ranges=[])
    assert math.isnan(decode(encode(scan), LaserScan).origin_x)


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


def test_new_fields_have_defaults_so_old_senders_stay_valid():
    old = msgspec.msgpack.encode({"type": "NavigateToRequest", "x": 1.0, "y": 2.0, "theta": 0.0})
    assert decode(old, NavigateToRequest).client == ""


def test_missing_required_field_is_named():
    with pytest.raises(DecodeError, match="missing required field `theta`"):
        decode(msgspec.msgpack.encode({"type": "NavigateToRequest", "x": 1.0, "y": 2.0}), NavigateToRequest)


def test_unknown_encoding_names_no_type():
    assert type_from_encoding("application/json") is None
    assert type_from_encoding("application/msgpack;Nope") is None


def test_every_key_has_a_message_type():
    assert set(TOPICS) == {"turtle1/cmd_vel", "turtle1/pose", "robot/status", "obstacles", "navigate_to/feedback"}
    assert SERVICES["navigate_to"] == (NavigateToRequest, NavigateToResponse)


def test_node_token_round_trip():
    info = NodeInfo(name="navigator", pid=42, host="box.local", start_ns=17)
    assert parse_node_token(node_token(info)) == info
    assert parse_node_token(node_token(NodeInfo(name="n", pid=1, host="we/ird*"))).host == "we_ird_"
    assert parse_node_token("@turtlectl/node/x") is None
    assert parse_node_token("@turtlectl/node/x/1/host/notanumber") is None
    assert parse_node_token("other/key") is None


def test_entity_token_round_trip_keeps_slashes_in_the_key():
    entity = EntityInfo(node="sim", pid=7, role="pub", type_name="Pose", key="turtle1/pose")
    assert parse_entity_token(entity_token(entity)) == entity
    assert parse_entity_token("@turtlectl/entity/sim/7/bad/Pose/k") is None


@pytest.mark.parametrize(
    "degrees, reduced",
    [(1e16, 280.0), (1e308, 296.0), (-1e-17, 0.0), (360.0, 0.0), (-45.0, 315.0), (720.5, 0.5), (-1e16, 80.0)],
)
def test_headings_are_reduced_in_degrees_exactly(degrees, reduced):
    assert degrees_0_360(degrees) == pytest.approx(reduced)
    assert 0.0 <= degrees_0_360(degrees) < 360.0
    assert -math.pi <= heading_radians(degrees) < math.pi
    assert heading_radians(degrees) == pytest.approx(wrap_radians(math.radians(reduced)))


def test_radians_read_as_degrees_in_0_360():
    assert heading_degrees(-1e-18) == 0.0 and heading_degrees(-math.pi / 2) == pytest.approx(270.0)
    assert heading_degrees(2 * math.pi) == 0.0
    assert wrap_radians(math.pi) == -math.pi and wrap_radians(1e300) < math.pi


def test_every_message_is_frozen_and_names_its_wire_tag_explicitly():
    """Issue 9: a renamed class must never change the wire format, and a reply is built, not mutated."""
    for t in ALL_TYPES:
        assert t.__struct_config__.frozen, t
        assert f'tag="{t.__struct_config__.tag}"' in inspect.getsource(t).splitlines()[0], t
    with pytest.raises(AttributeError):
        Pose(x=1.0, y=2.0, theta=0.0).x = 3.0  # type: ignore[misc]

    class RenamedTwist(Message, tag="Twist"):
        linear: float = 0.0

    assert encoding_for(RenamedTwist) == "application/msgpack;Twist"
    assert b"Twist" in encode(RenamedTwist(linear=1.0)) and b"Renamed" not in encode(RenamedTwist())
