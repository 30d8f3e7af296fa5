"""User types in the real system: the Python client calls a service of the user's own types
(and reads its answer); echo counts the undecodable payloads on a key however it ends, a
--timeout included."""

from __future__ import annotations

import json
import subprocess

import msgspec
import pytest

import turtlectl
from tests.integration.harness import turtlectl as command
from tests.integration.test_user_types import walls_system
from turtlectl import Message

pytestmark = pytest.mark.integration


class WallReset(Message, tag="wall/WallReset"):
    """The test's own copy of the project's request type (same fields, same full name: the
    project's wall.py is package ``wall``)."""

    to: float


@pytest.fixture(scope="module")
def system(tmp_path_factory):
    with walls_system(tmp_path_factory) as system:
        yield system


def test_the_client_calls_a_service_of_the_users_own_types(system):
    with turtlectl.Client(system.endpoint) as client:
        answer = client.call("wall/restart", WallReset(to=1.25))
    assert type(answer).__name__ == "WallState" and answer.distance == 1.25


def echo_while_putting(system, args: list[str], key: str, payload: bytes, encoding: str) -> tuple[str, str]:
    """``turtlectl echo ARGS`` run while ``payload`` is put on ``key`` again and again, until it
    ends: its stdout and stderr."""
    echo = subprocess.Popen(
        [*command(), "echo", *args, "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        system.wait_until(
            lambda: echo.poll() is not None or system.session.put(key, payload, encoding=encoding), 20.0, "echo ended"
        )
        return echo.communicate(timeout=20)
    finally:
        if echo.poll() is None:
            echo.kill()


def test_echo_counts_undecodable_payloads_even_when_it_times_out(system):
    garbage = b"\xc1\xc1\xc1"  # not msgpack at all
    _, err = echo_while_putting(
        system, ["raw/garbage", "--timeout", "3"], "raw/garbage", garbage, "application/msgpack;Mystery"
    )
    assert err.count("skipped a message on raw/garbage") == 1, err
    assert "messages on raw/garbage in all" in err, err


def test_json_of_an_untyped_undescribed_payload_says_type_null(system):
    data = msgspec.msgpack.encode({"a": 1})
    out, err = echo_while_putting(system, ["raw/plain", "--once", "--json"], "raw/plain", data, "application/msgpack")
    assert json.loads(out) == {"type": None, "undescribed": True, "a": 1}, (out, err)
