"""runtime.client.goals: a goal given up on is said in the words of the goal service it went to."""

from __future__ import annotations

import pytest

from turtlectl.messages import Ack
from turtlectl.runtime.client.errors import ExitCode, exit_code
from turtlectl.runtime.client.goals import GoalService, given_up, navigate_to

TIMED_OUT = "the goal did not end within --timeout 2 s"
PATROL = GoalService("patrol/laps", "StudentLapsResult", ("patrol",))


@pytest.mark.parametrize("interrupted", [False, True])
def test_a_user_s_goal_service_is_named_with_the_node_serving_it_not_the_navigator(interrupted):
    why = "interrupted" if interrupted else TIMED_OUT
    lead = "interrupted: " if interrupted else f"{TIMED_OUT}; "
    canceled = given_up(why, Ack(detail="canceled the goal (2)"), interrupted, PATROL)
    assert canceled.message == f"{lead}the goal service patrol/laps (patrol) canceled the goal"
    assert exit_code(canceled) == (ExitCode.INTERRUPTED if interrupted else ExitCode.FAILED)
    ended = given_up(why, Ack(ok=False, detail="no goal is running"), interrupted, PATROL)
    assert (
        ended.message
        == f"{lead}the goal had ended meanwhile (the goal service patrol/laps (patrol): no goal is running)"
    )
    unconfirmed = given_up(why, "nothing serves patrol/laps/cancel", interrupted, PATROL)
    assert exit_code(unconfirmed) == ExitCode.CANCEL_UNCONFIRMED
    assert unconfirmed.message == (
        f"{lead}nobody confirmed the cancel: the goal may still be running "
        "(nothing serves patrol/laps/cancel; `turtlectl call patrol/laps/cancel` asks again)"
    )
    assert "navigator" not in canceled.message + ended.message + unconfirmed.message


@pytest.mark.parametrize("key", ["navigate_to", "turtle2/navigate_to", "lab1/turtle2/navigate_to"])
def test_every_navigate_to_keeps_the_navigator_s_words(key):
    service = navigate_to(key)
    assert service.server == "the navigator" and service.cancel_key == f"{key}/cancel"
    assert given_up(TIMED_OUT, Ack(), False, service).message == f"{TIMED_OUT}; the navigator canceled the goal"
    assert "the turtle may still be driving" in given_up(TIMED_OUT, "silence", False, service).message


def test_a_goal_service_without_known_servers_is_named_by_its_key():
    assert GoalService("arm/pick", "PickResult").server == "the goal service arm/pick"


def test_a_goal_canceled_by_its_timeout_or_by_a_cancel_is_one_error_carrying_the_result_and_last_feedback():
    from turtlectl.messages import NavigateToFeedback, NavigateToResponse
    from turtlectl.runtime.client.errors import CancelUnconfirmed, GoalCanceled
    from turtlectl.runtime.client.goals import API_LIMIT, CLI_LIMIT, canceled

    why = f"the goal did not end within {API_LIMIT.format(1.5)}"
    assert why == "the goal did not end within timeout=1.5 s"  # the Python client's own terms
    response = NavigateToResponse(success=False, time_taken=1.6, reason="canceled", x=3.2, y=1.0)
    feedback = NavigateToFeedback(
        state="driving", distance_remaining=6.9, heading_remaining=0.0, eta=3.0, elapsed=1.5, x=3.1, y=1.0, theta=0.0
    )
    timed_out = given_up(why, Ack(detail="canceled"), False, response=response, feedback=feedback, timeout=1.5)
    assert isinstance(timed_out, GoalCanceled) and exit_code(timed_out) == ExitCode.FAILED
    assert timed_out.message == "the goal did not end within timeout=1.5 s; the navigator canceled the goal"
    assert (timed_out.response, timed_out.feedback, timed_out.timeout) == (response, feedback, 1.5)
    by_anyone = canceled(navigate_to(), response, feedback)
    assert isinstance(by_anyone, GoalCanceled) and exit_code(by_anyone) == ExitCode.FAILED
    assert by_anyone.message == "the navigator canceled the goal" and by_anyone.timeout is None
    assert (by_anyone.response, by_anyone.feedback) == (response, feedback)
    unconfirmed = given_up(why, "silence", False, feedback=feedback)
    assert isinstance(unconfirmed, CancelUnconfirmed) and unconfirmed.feedback == feedback
    # the command line's goto (built on the Python client, with timeout_named=CLI_LIMIT) says it in its own terms
    in_cli_terms = given_up(f"the goal did not end within {CLI_LIMIT.format(1.5)}", Ack(detail="canceled"), False)
    assert in_cli_terms.message.startswith("the goal did not end within --timeout 1.5 s; ")
    assert str(timed_out) == timed_out.message
