"""`interface show` of a user type (from the description its
nodes serve) is as complete as a built-in's: Python-like field types, `required`, a range or
the values of each field, its nested Structs shown too, its keys from the live graph, and an
unknown name answered with the live types as well as the built-ins."""

from __future__ import annotations

import enum
from typing import Annotated

import msgspec
import pytest

from turtlectl.cli.tools import interface
from turtlectl.messages import Message
from turtlectl.messages.described import describe
from turtlectl.runtime.client.errors import BadInput
from turtlectl.runtime.client.graph import Graph, ServiceRow, TopicRow


class Side(enum.Enum):
    LEFT = "left"
    RIGHT = "right"


class Point(msgspec.Struct, frozen=True):
    """A point seen."""

    x: float
    y: float = 0.5


class Survey(Message, tag="Survey"):
    """What a survey found."""

    speed: Annotated[float, msgspec.Meta(gt=0, le=8)]  # m/s: how fast it went
    count: Annotated[int, msgspec.Meta(ge=0)] = 0  # -: how many
    name: str = "x"  # -: who ran it
    blob: bytes = b""  # -: the raw frame
    points: list[Point] = []  # m: points seen
    span: tuple[float, float] = (0.0, 0.0)  # m: from, to
    tally: dict[str, int] = {}  # -: hits per group
    home: Point | None = None  # m: where it started
    side: Side = Side.LEFT  # -: which side
    ok: bool = True  # -: whether it went well
    scale: float = 1.5  # -: a factor


LIVE = {"Survey": {"surveyor": describe(Survey)}}


def _fields(shown: dict) -> dict[str, dict]:
    return {f["name"]: f for f in shown["fields"]}


def test_a_user_type_s_fields_have_python_like_types():
    fields = _fields(interface.description("Survey", LIVE))
    types = {name: f["type"] for name, f in fields.items()}
    assert types == {
        "speed": "float",
        "count": "int",
        "name": "str",
        "blob": "bytes",
        "points": "list[Point]",
        "span": "tuple[float, float]",
        "tally": "dict[str, int]",
        "home": "Point | None",
        "side": "Side",
        "ok": "bool",
        "scale": "float",
    }


def test_required_fields_say_so_and_defaults_read_as_a_built_in_s():
    fields = _fields(interface.description("Survey", LIVE))
    assert fields["speed"]["default"] == "required"
    assert fields["count"]["default"] == "0" and fields["name"]["default"] == '"x"'
    assert fields["scale"]["default"] == "1.5" and fields["span"]["default"] == "[0.0,0.0]"
    assert fields["home"]["default"] == "null" and fields["side"]["default"] == '"left"'


def test_the_range_column_gives_values_bounds_or_any():
    fields = _fields(interface.description("Survey", LIVE))
    assert fields["side"]["range"] == "left, right"
    assert fields["speed"]["range"] == "> 0 and <= 8"
    assert fields["count"]["range"] == ">= 0"
    assert fields["name"]["range"] == "any" and fields["points"]["range"] == "any"
    assert fields["speed"]["unit"] == "m/s" and fields["speed"]["meaning"] == "how fast it went"


def test_the_text_shows_the_columns():
    text = interface.description_text(interface.description("survey", LIVE))
    speed = next(line for line in text.splitlines() if line.startswith("speed "))
    assert speed.split() == ["speed", "float", "required", "m/s", ">", "0", "and", "<=", "8"]


def test_a_nested_struct_of_a_live_type_is_shown_from_its_definition():
    shown = interface.description("point", LIVE)
    assert shown["type"] == "Point" and shown["nested_in"] == ["Survey"]
    assert shown["doc"] == "A point seen."
    assert [(f["name"], f["type"], f["default"], f["unit"], f["range"]) for f in shown["fields"]] == [
        ("x", "float", "required", "-", "any"),
        ("y", "float", "0.5", "-", "any"),
    ]
    text = interface.description_text(shown)
    assert text.startswith("Point: a map nested in Survey") and "keys: (none of its own)" in text


def test_a_live_type_s_keys_come_from_the_live_graph():
    graph = Graph(
        nodes=[],
        topics=[
            TopicRow(key="survey/state", type="Survey", publishers=["surveyor"], subscribers=[]),
            TopicRow(key="turtle1/cmd_vel", type="Twist", publishers=[], subscribers=["sim"]),
        ],
        services=[ServiceRow(key="survey/run", type="Survey", servers=["surveyor"])],
    )
    keys = interface.keys_by_type(graph)
    assert keys["Survey"] == ["survey/run", "survey/state"]
    shown = interface.description("Survey", LIVE, keys)
    assert shown["keys"] == ["survey/run", "survey/state"]
    assert "keys: survey/run, survey/state" in interface.description_text(shown)
    row = next(r for r in interface.listing(LIVE, keys) if r["type"] == "Survey")
    assert row["keys"] == ["survey/run", "survey/state"]


def test_an_unknown_name_lists_the_built_ins_then_the_live_types():
    with pytest.raises(BadInput) as caught:
        interface.description("Odometry", LIVE)
    message = str(caught.value)
    assert message.startswith("unknown message type 'Odometry' (known: turtlectl/Ack,"), message
    assert "Twist" in message and "Survey" in message
    assert message.index("Twist") < message.index("Survey"), message
