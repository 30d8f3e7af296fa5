"""cli.tools.routerwatch: one line when the router is lost, one when it is back, none per check;
--exit-on-loss raises RouterLost (exit code 3) instead; checks at most every ROUTER_CHECK s."""

from __future__ import annotations

import pytest

from turtlectl.cli.tools.routerwatch import RouterWatch
from turtlectl.runtime.client.errors import ExitCode, exit_code
from turtlectl.runtime.client.services import RouterLost
from turtlectl.runtime.client.session import ROUTER_CHECK

ENDPOINT = "tcp/127.0.0.1:7447"


def test_a_lost_router_is_said_once_and_its_return_once_with_how_long_it_lasted():
    gone = [False]
    watch = RouterWatch(lambda: gone[0], ENDPOINT, "messages on robot/status")
    said = []
    t = 0.0
    for step in range(40):
        t = step * 0.1
        gone[0] = 1.0 <= t < 2.6
        if (line := watch.check(t)) is not None:
            said.append((round(t, 1), line))
    assert said == [
        (
            1.0,
            f"lost the router at {ENDPOINT}: waiting for it to come back, no messages on robot/status meanwhile "
            "(--exit-on-loss exits instead)",
        ),
        (3.0, f"the router at {ENDPOINT} is back after 2.0 s: messages on robot/status again"),
    ]
    assert not watch.lost


def test_the_router_is_asked_at_most_every_check_period():
    asked = []
    watch = RouterWatch(lambda: asked.append(1) or False, ENDPOINT, "log records")
    for step in range(100):
        watch.check(step * 0.01)
    assert len(asked) == int(1.0 / ROUTER_CHECK)


def test_exit_on_loss_raises_router_lost_with_exit_code_3():
    watch = RouterWatch(lambda: True, ENDPOINT, "log records", exit_on_loss=True)
    with pytest.raises(RouterLost) as raised:
        watch.check(0.0)
    assert exit_code(raised.value) == ExitCode.UNREACHABLE
    assert str(raised.value) == f"lost the router at {ENDPOINT}: no more log records (did `turtlectl launch` stop?)"
