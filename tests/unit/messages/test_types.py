"""messages.types: every type has a sample, defaults for new fields, frozen Structs with explicit wire tags; NavigateToFeedback.state is a GoalState, not free text, and the wire does not notice."""

import inspect
import math

import msgspec
import pytest

from tests.unit.messages.samples import SAMPLES
from turtlectl.messages import (
    ALL_TYPES,
    DecodeError,
    GoalState,
    LaserScan,
    Message,
    NavigateToFeedback,
    NavigateToRequest,
    Pose,
    decode,
    encode,
    encoding_for,
    to_json,
)
from turtlectl.messages.codec import type_name, type_short_name


def test_samples_cover_every_type():
    assert {type(m) for m in SAMPLES} == set(ALL_TYPES)


def test_scan_origin_defaults_to_unknown():
    scan = LaserScan(angle_min=0, angle_max=0, angle_increment=0, range_min=0, range_max=1, ranges=[])
    assert math.isnan(decode(encode(scan), LaserScan).origin_x)


def test_new_fields_have_defaults_so_old_senders_stay_valid():
    old = msgspec.msgpack.encode({"type": "turtlectl/NavigateToRequest", "x": 1.0, "y": 2.0, "theta": 0.0})
    assert decode(old, NavigateToRequest).client == ""


def test_every_message_is_frozen_and_names_its_wire_tag_explicitly():
    """A renamed class must never change the wire format, and a reply is built, not mutated."""
    for t in ALL_TYPES:
        assert t.__struct_config__.frozen, t
        assert f'tag="{type_short_name(t)}"' in inspect.getsource(t).splitlines()[0], t
        assert type_name(t) == f"turtlectl/{type_short_name(t)}", t
    with pytest.raises(AttributeError):
        Pose(x=1.0, y=2.0, theta=0.0).x = 3.0  # type: ignore[misc]

    class RenamedTwist(Message, tag="Twist"):
        linear: float = 0.0

    assert encoding_for(RenamedTwist) == "application/msgpack;tests/Twist"  # declared in the package tests
    assert b"tests/Twist" in encode(RenamedTwist(linear=1.0)) and b"Renamed" not in encode(RenamedTwist())


def feedback(state) -> NavigateToFeedback:
    return NavigateToFeedback(
        state=state, distance_remaining=1.0, heading_remaining=2.0, eta=0.5, elapsed=0.1, x=1.0, y=2.0, theta=3.0
    )


def test_the_states_are_exactly_the_words_the_wire_always_carried():
    assert [s.value for s in GoalState] == ["turning", "driving", "blocked", "replanning"]  # the last: a detour


@pytest.mark.parametrize("state", list(GoalState))
def test_a_state_travels_as_its_word_and_comes_back_as_the_enum(state):
    payload = encode(feedback(state))
    assert payload == encode(feedback(state.value))  # the same bytes as the plain string
    back = decode(payload, NavigateToFeedback)
    assert back.state is state
    assert f'"state":"{state.value}"' in to_json(back).decode()
    assert f"{back.state:8s}" == f"{state.value:8s}"  # what `goto` prints


def test_a_state_outside_the_vocabulary_is_refused():
    payload = encode(feedback("dancing"))
    with pytest.raises(DecodeError, match=r"Invalid enum value 'dancing' - at `\$.state`"):
        decode(payload, NavigateToFeedback)
