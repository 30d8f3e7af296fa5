"""A user's own message type needs nothing but its class.  The codec builds a type's
decoder on first use (no fixed table), every failure is the one DecodeError (a ValueError) the
runtime handles, and the supported field types round-trip: nested Structs, lists, tuples,
dicts, optional fields, enums and bytes."""

from __future__ import annotations

import enum

import msgspec
import pytest

from turtlectl.messages import Message, decode, decode_any, encode, encoding_for, type_from_encoding
from turtlectl.messages.codec import DecodeError, register


class Side(enum.Enum):
    LEFT = "left"
    RIGHT = "right"


class Point(msgspec.Struct, frozen=True):
    x: float
    y: float


class WallState(Message, tag="WallState"):
    """What the wall follower sees."""

    distance: float  # m: to the wall
    side: Side = Side.LEFT  # -: which side the wall is on
    corners: list[Point] = []  # m: corners seen
    span: tuple[float, float] = (0.0, 0.0)  # m: from, to
    counts: dict[str, int] = {}  # -: hits per beam group
    note: str | None = None  # -: anything to say
    raw: bytes = b""  # -: the raw frame


def sample() -> WallState:
    return WallState(
        distance=0.8,
        side=Side.RIGHT,
        corners=[Point(1.0, 2.0), Point(3.0, 4.0)],
        span=(0.5, 1.5),
        counts={"front": 3},
        note="close",
        raw=b"\x00\x01",
    )


def test_a_user_type_round_trips_with_every_supported_field_type():
    assert decode(encode(sample()), WallState) == sample()


def test_a_bad_payload_of_a_user_type_is_the_one_decode_error_never_a_key_error():
    with pytest.raises(DecodeError, match="not a valid tests/WallState"):
        decode(b"\x93garbage", WallState)
    with pytest.raises(ValueError):
        decode(encode(sample()), Point)  # type: ignore[type-var]  # not a message at all


def test_a_used_type_is_known_by_its_encoding_and_decoded_by_its_tag():
    register(WallState)
    assert type_from_encoding(encoding_for(WallState)) is WallState
    assert decode_any(encode(sample())) == sample()


def test_a_second_class_under_a_taken_name_is_refused():
    class Other(Message, tag="WallState"):
        level: int

    with pytest.raises(ValueError, match="WallState"):
        register(Other)


def test_a_node_publishes_and_receives_a_user_type_and_survives_garbage_on_it():
    """Through the real Node (FakeNode): a type without stamp/seq is published as it is (it
    raised TypeError: no field 'stamp'), a subscription decodes it, and garbage on its key is
    logged and dropped, the node running on (the codec's KeyError stopped the node)."""
    import turtlectl
    from turtlectl.testing import FakeNode

    class Follower:
        Params = msgspec.defstruct("FollowerParams", [])
        Interface = turtlectl.Interface(publishes=("wall/state",), subscribes=("wall/in",))

        def __init__(self, node):
            self.got: list[WallState] = []
            self.pub = node.publisher("wall/state", WallState)
            node.subscribe("wall/in", WallState, self.got.append)

    fake = FakeNode(Follower)
    fake.instance.pub.publish(sample())
    assert fake.published("wall/state") == [sample()]
    fake.deliver("wall/in", b"\x01\x02garbage")
    fake.deliver("wall/in", sample())
    assert fake.instance.got == [sample()]


def test_a_description_round_trips_and_its_hash_is_what_the_interfaces_page_says():
    """An independent client recomputes the hash from the served JSON with any JSON library
    (sorted keys, no spaces) and rebuilds a class that decodes the type's payloads."""
    import hashlib
    import json

    from turtlectl.messages.described import TypeDescription, describe, struct_from

    served = msgspec.json.encode(describe(WallState))
    plain = json.loads(served)
    canonical = json.dumps(
        {"name": plain["name"], "schema": plain["schema"]}, sort_keys=True, separators=(",", ":"), ensure_ascii=False
    )
    assert plain["hash"] == "TH01_" + hashlib.sha256(canonical.encode()).hexdigest()
    assert [(f["name"], f["unit"], f["meaning"]) for f in plain["fields"]][:2] == [
        ("distance", "m", "to the wall"),
        ("side", "-", "which side the wall is on"),
    ]
    rebuilt = struct_from(msgspec.json.decode(served, type=TypeDescription))
    again = decode(encode(sample()), rebuilt)
    assert again.corners[1].y == 4.0 and again.side.value == "right" and again.raw == b"\x00\x01"


def test_every_built_in_type_is_described_the_same_way_with_its_units():
    from turtlectl.messages import ALL_TYPES
    from turtlectl.messages.described import describe

    for cls in ALL_TYPES:
        described = describe(cls)
        assert described.hash.startswith("TH01_") and [f.name for f in described.fields] == list(cls.__struct_fields__)
    pose = {f.name: f.unit for f in describe(next(t for t in ALL_TYPES if t.__name__ == "Pose")).fields}
    assert pose["x"] == "m" and pose["theta"] == "rad"


def test_every_built_in_type_can_be_rebuilt_from_its_description():
    """A field typed Any (SetParameter.value) is described with a default and no type: it was
    refused ("not supported")."""
    from turtlectl.messages import ALL_TYPES
    from turtlectl.messages.described import describe, struct_from

    for cls in ALL_TYPES:
        rebuilt = struct_from(describe(cls))
        assert list(rebuilt.__struct_fields__) == list(cls.__struct_fields__), cls.__name__


def test_a_rebuilt_class_fills_defaults_as_the_original_does():
    """`pub` leaving `raw: bytes = b""` out: the rebuilt class sends bytes, not the JSON default
    "" (a str) that the real node would drop (Expected bytes, got str)."""
    from turtlectl.messages.described import describe, struct_from

    rebuilt = struct_from(describe(WallState))
    built = msgspec.json.decode(b'{"distance": 1.0}', type=rebuilt)
    original = decode(encode(built), WallState)
    assert original.raw == b"" and original.side is Side.LEFT and original.span == (0.0, 0.0)


def test_a_users_own_class_takes_the_place_of_one_rebuilt_from_the_wire():
    """A script that learnt a type through the client, then uses its own class of that name (the
    serial test run found it: an integration test's client had learnt WallState first)."""
    from turtlectl.messages.codec import TYPES_BY_NAME
    from turtlectl.messages.described import describe, struct_from

    class Seen(Message, tag="UnitSeenType"):
        n: int  # -: a count

    register(struct_from(describe(Seen)))
    assert register(Seen) is Seen and TYPES_BY_NAME["tests/UnitSeenType"] is Seen
    assert decode_any(encode(Seen(n=2))) == Seen(n=2)
    with pytest.raises(ValueError, match="two message types named 'tests/UnitSeenType'"):
        register(struct_from(describe(Seen)))  # a rebuilt class never replaces a real one
