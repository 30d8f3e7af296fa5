"""A goal given up on (--timeout, Ctrl-C) is canceled, and the cancel's answer is checked:
against a navigator that serves navigate_to but not navigate_to/cancel
(or never answers it), goto and call say plainly that nobody confirmed the cancel and exit
5, instead of "the navigator cancels it" while the turtle drives on."""

from __future__ import annotations

import select
import signal
import subprocess
import sys
import time
from collections.abc import Iterator

import pytest
import zenoh

from tests.integration.harness import ROOT, Router, turtlectl
from turtlectl.runtime.session import client_config, close_session

pytestmark = pytest.mark.integration

UNCONFIRMED = "nobody confirmed the cancel: the turtle may still be driving to the goal"


class FakeNavigator:
    """tests/integration/fake_navigator.py on a router of its own, ready once its token shows."""

    def __init__(self, endpoint: str, *how: str):
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "tests.integration.fake_navigator", endpoint, *how],
            cwd=ROOT,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        session = zenoh.open(client_config(endpoint, 3.0))
        try:
            deadline = time.monotonic() + 20.0
            while not [r for r in session.liveliness().get("fake/navigator", timeout=1.0) if r.ok is not None]:
                assert self.proc.poll() is None, "the fake navigator exited"
                assert time.monotonic() < deadline, "the fake navigator never served"
        finally:
            close_session(session)

    def wait_goal(self, timeout: float = 10.0) -> None:
        """Until the fake says it took a goal (an event, not a sleep)."""
        ready, _, _ = select.select([self.proc.stdout], [], [], timeout)
        assert ready and self.proc.stdout.readline().strip() == "goal"

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.wait(5)


@pytest.fixture(scope="module")
def router() -> Iterator[Router]:
    router = Router()
    router.start()
    yield router
    router.kill()


@pytest.fixture(params=["no-cancel", "silent-cancel"])
def fake(router, request) -> Iterator[FakeNavigator]:
    navigator = FakeNavigator(router.endpoint, *(() if request.param == "no-cancel" else (request.param,)))
    yield navigator
    navigator.stop()


def why(fake: FakeNavigator) -> str:
    silent = fake.proc.args[-1] == "silent-cancel"
    return "navigate_to/cancel did not answer within 2 s" if silent else "nothing serves navigate_to/cancel"


@pytest.mark.parametrize("command", ["goto 5 5 0", 'call navigate_to {"x":5,"y":5,"theta":0}'])
def test_a_timeout_whose_cancel_nobody_confirms_says_so_and_exits_5(router, fake, command):
    result = subprocess.run(
        [*turtlectl(), *command.split(), "--timeout", "1", "--connect", router.endpoint],
        capture_output=True,
        text=True,
        timeout=30,
        stdin=subprocess.DEVNULL,
    )
    assert result.returncode == 5, result.stderr
    assert f"did not end within --timeout 1 s; {UNCONFIRMED} ({why(fake)}" in result.stderr
    assert "cancels it" not in result.stderr and "canceled" not in result.stderr


@pytest.mark.parametrize("command", ["goto 5 5 0", 'call navigate_to {"x":5,"y":5,"theta":0}'])
def test_ctrl_c_whose_cancel_nobody_confirms_says_so_and_exits_5(router, fake, command):
    proc = subprocess.Popen(
        [*turtlectl(), *command.split(), "--connect", router.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        text=True,
    )
    try:
        fake.wait_goal()
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=15)
    finally:
        proc.kill()
    assert proc.returncode == 5, err
    assert f"interrupted: {UNCONFIRMED} ({why(fake)}" in err
    assert "Traceback" not in err
