"""NavigateToFeedback.state is a GoalState, not free text, and the wire does not notice."""

import pytest

from messages import DecodeError, GoalState, NavigateToFeedback, decode, encode, to_json


def feedback(state) -> NavigateToFeedback:
    return NavigateToFeedback(
        state=state, distance_remaining=1.0, heading_remaining=2.0, eta=0.5, elapsed=0.1, x=1.0, y=2.0, theta=3.0
    )


def test_the_states_are_exactly_the_words_the_wire_always_carried():
    assert [s.value for s in GoalState] == ["turning", "driving", "blocked"]


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
