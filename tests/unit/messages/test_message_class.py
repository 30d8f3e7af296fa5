"""messages.jsonform.message_class: a recording's JSON Schema of a type turtlectl was not built
with made back into a class that reads the recorded JSON and sends the same msgpack
bytes as the original; a schema that is no message's is DescriptionError."""

from __future__ import annotations

import json
import math

import msgspec
import pytest

from turtlectl.messages import Message, encode
from turtlectl.messages.described import DescriptionError
from turtlectl.messages.jsonform import from_json, json_schema, message_class, to_json


class Spot(msgspec.Struct, frozen=True):
    x: float
    y: float


class RecordedState(Message, tag="RecordedState"):
    """A user's type."""

    distance: float
    side: str = "left"
    spots: list[Spot] = []
    maybe: float | None = None
    unset: float = float("nan")
    stamp: int = 0
    seq: int = 0


def test_the_class_from_a_recorded_schema_sends_the_same_bytes():
    recorded = json.loads(json.dumps(json_schema(RecordedState)))  # as the file holds it
    rebuilt = message_class("tests/RecordedState", recorded)
    original = RecordedState(distance=math.inf, spots=[Spot(1.0, 2.0)], maybe=3.0, stamp=5, seq=3)
    again = from_json(to_json(original), rebuilt)
    assert encode(again) == encode(original)
    assert math.isnan(rebuilt(distance=1.0).unset)  # a spelled NaN default is a float again
    assert json_schema(rebuilt) == {k: v for k, v in recorded.items() if k != "description"}


@pytest.mark.parametrize("schema", [{}, {"type": "object"}, {"properties": {"a": {"type": "frob"}}}, []])
def test_a_schema_that_is_no_message_is_a_description_error(schema):
    with pytest.raises(DescriptionError):
        message_class("Odometry", schema)  # type: ignore[arg-type]
