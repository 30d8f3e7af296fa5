"""runtime.client.services: which answers are failures."""

import pytest

from tests.unit.messages.samples import FEEDBACK
from turtlectl.messages import (
    Ack,
    NavigateToResponse,
)
from turtlectl.runtime.client.errors import ExitCode, Interrupted, exit_code
from turtlectl.runtime.client.goals import given_up
from turtlectl.runtime.client.services import reply_code


def test_an_answer_that_says_no_is_exit_code_1():
    assert reply_code(Ack(ok=False, detail="no goal is running")) == ExitCode.FAILED
    assert reply_code(Ack()) == ExitCode.OK
    assert reply_code(NavigateToResponse(success=False, time_taken=0.0, reason="canceled")) == ExitCode.FAILED
    assert reply_code(NavigateToResponse(success=True, time_taken=1.0)) == ExitCode.OK
    assert reply_code(FEEDBACK) == ExitCode.OK


# -- a goal given up on: its cancel's answer --------------------------------------------
TIMED_OUT = "the goal did not end within --timeout 2 s"


@pytest.mark.parametrize("interrupted", [False, True])
@pytest.mark.parametrize(
    "answer", ["nothing serves navigate_to/cancel", "navigate_to/cancel did not answer within 2 s"]
)
def test_a_cancel_nobody_confirmed_is_said_plainly_with_its_own_exit_code(answer, interrupted):
    error = given_up("interrupted" if interrupted else TIMED_OUT, answer, interrupted)
    assert exit_code(error) == ExitCode.CANCEL_UNCONFIRMED == 5
    lead = "interrupted: " if interrupted else f"{TIMED_OUT}; "
    assert error.message == (
        f"{lead}nobody confirmed the cancel: the turtle may still be driving to the goal ({answer}; "
        "`turtlectl cancel` asks again)"
    )


def test_a_confirmed_cancel_keeps_the_exit_code_of_a_goal_not_reached_or_of_ctrl_c():
    ack = Ack(detail="canceled the goal (5, 5, 0 deg)")
    timed_out = given_up(TIMED_OUT, ack, interrupted=False)
    assert exit_code(timed_out) == ExitCode.FAILED
    assert timed_out.message == f"{TIMED_OUT}; the navigator canceled the goal"
    interrupted = given_up("interrupted", ack, interrupted=True)
    assert isinstance(interrupted, Interrupted) and exit_code(interrupted) == ExitCode.INTERRUPTED
    assert interrupted.message == "interrupted: the navigator canceled the goal"


def test_a_navigator_with_no_goal_running_any_more_confirms_too():
    """The goal ended on its own just before the cancel: the navigator answered, nothing drives."""
    error = given_up(TIMED_OUT, Ack(ok=False, detail="no goal is running"), interrupted=False)
    assert exit_code(error) == ExitCode.FAILED
    assert error.message == f"{TIMED_OUT}; the goal had ended meanwhile (the navigator: no goal is running)"
