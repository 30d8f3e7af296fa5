"""messages.jsonform: JSON that gives back every message exactly (inf and NaN included), and a
JSON Schema per type that Foxglove reads (an object at the top) and that the JSON satisfies."""

from __future__ import annotations

import json
import math

import msgspec
import pytest

from tests.unit.messages.samples import SAMPLES
from turtlectl.messages import LaserScan, Pose, decode_any, encode
from turtlectl.messages.jsonform import NON_FINITE, JsonFormError, from_json, json_schema, to_json
from turtlectl.messages.types import ALL_TYPES


@pytest.mark.parametrize("msg", SAMPLES, ids=lambda m: type(m).__name__)
def test_every_message_comes_back_identical(msg):
    msg = decode_any(encode(msg))  # as received: floats where the sample wrote ints
    again = from_json(to_json(msg))
    assert encode(again) == encode(msg)  # the bytes on the wire: NaN compares unequal to itself
    assert encode(from_json(to_json(msg), type(msg))) == encode(msg)


def test_non_finite_floats_are_spelled_and_come_back():
    scan = LaserScan(
        angle_min=0.0,
        angle_max=1.0,
        angle_increment=0.5,
        range_min=0.0,
        range_max=5.0,
        ranges=[1.0, math.inf, -math.inf, math.nan],
    )
    data = json.loads(to_json(scan))  # plain JSON: any reader parses it
    assert data["ranges"][1:] == ["Infinity", "-Infinity", "NaN"] and data["origin_x"] == "NaN"
    again = from_json(to_json(scan), LaserScan)
    assert again.ranges[:3] == [1.0, math.inf, -math.inf] and math.isnan(again.ranges[3])


def test_a_string_field_keeps_a_non_finite_spelling_as_text():
    from turtlectl.messages import NavigateToResponse

    response = NavigateToResponse(success=False, time_taken=1.0, reason="NaN", detail="Infinity")
    again = from_json(to_json(response))
    assert again.reason == "NaN" and again.detail == "Infinity"


def test_what_is_not_a_message_is_refused_with_a_reason():
    with pytest.raises(JsonFormError, match="not a valid turtlectl/Pose"):
        from_json(b'{"type": "Pose", "x": 1}', Pose)
    with pytest.raises(JsonFormError, match="not a valid message"):
        from_json(b"not json")
    with pytest.raises(JsonFormError):
        from_json(b'{"type": "Pose", "x": 1, "y": 2, "theta": 0, "extra": 1}')  # unknown fields stay forbidden


@pytest.mark.parametrize("msg_type", ALL_TYPES, ids=lambda t: t.__name__)
def test_each_schema_is_an_object_named_by_the_wire_type(msg_type):
    schema = json_schema(msg_type)
    assert schema["type"] == "object" and schema["title"] == msg_type.__struct_config__.tag
    assert "properties" in schema and "$ref" not in schema


def test_the_json_satisfies_its_schema_including_the_spelled_floats():
    """Checked by hand for the shapes that matter (no jsonschema package needed): every number
    property allows the three spellings, and the required fields are all there."""
    schema = json_schema(LaserScan)
    ranges = schema["properties"]["ranges"]["items"]
    assert {"enum": list(NON_FINITE)} in ranges["anyOf"] and {"type": "number"} in ranges["anyOf"]
    assert {"enum": list(NON_FINITE)} in schema["properties"]["origin_x"]["anyOf"]
    data = json.loads(to_json(SAMPLES[3]))
    assert set(schema["required"]) <= set(data)
    assert msgspec.json.decode(json.dumps(schema))  # valid JSON as written into a recording
