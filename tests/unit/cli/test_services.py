"""cli.services: which answers are failures."""

from cli.errors import ExitCode
from cli.services import reply_code
from messages import (
    Ack,
    NavigateToResponse,
)
from tests.unit.messages.samples import FEEDBACK


def test_an_answer_that_says_no_is_exit_code_1():
    assert reply_code(Ack(ok=False, detail="no goal is running")) == ExitCode.FAILED
    assert reply_code(Ack()) == ExitCode.OK
    assert reply_code(NavigateToResponse(success=False, time_taken=0.0, reason="canceled")) == ExitCode.FAILED
    assert reply_code(NavigateToResponse(success=True, time_taken=1.0)) == ExitCode.OK
    assert reply_code(FEEDBACK) == ExitCode.OK
