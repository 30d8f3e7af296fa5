"""cli.services: which answers are failures."""

from cli.errors import ExitCode
from cli.services import reply_code
from messages import (
    Ack,
    NavigateToFeedback,
    NavigateToResponse,
)

FEEDBACK = NavigateToFeedback(
    state="driving",
    distance_remaining=10.123,
    heading_remaining=179.9,
    eta=12.3,
    elapsed=14.5,
    x=11.08,
    y=11.08,
    theta=359.96,
    goal_x=1,
    goal_y=1,
    goal_theta=0,
)


def test_an_answer_that_says_no_is_exit_code_1():
    assert reply_code(Ack(ok=False, detail="no goal is running")) == ExitCode.FAILED
    assert reply_code(Ack()) == ExitCode.OK
    assert reply_code(NavigateToResponse(success=False, time_taken=0.0, reason="canceled")) == ExitCode.FAILED
    assert reply_code(NavigateToResponse(success=True, time_taken=1.0)) == ExitCode.OK
    assert reply_code(FEEDBACK) == ExitCode.OK
