"""cli.system.supervisor.router: the one way a router is opened or joined, and what its failures say."""

from __future__ import annotations

import socket
import time

import pytest

from turtlectl.cli.errors import CannotStart, ExitCode, Unreachable, exit_code
from turtlectl.cli.system.supervisor.router import free_port_near, join_router, open_router, port_in_use
from turtlectl.runtime.session import close_session


def test_a_busy_port_is_cannot_start_naming_the_command_with_a_free_port():
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        for command in ("launch", "router"):
            with pytest.raises(CannotStart) as err:
                close_session(open_router(port, "127.0.0.1", command))
            text = err.value.message
            assert text.startswith(f"cannot listen on tcp/127.0.0.1:{port}: the port is already in use")
            assert f"another `turtlectl {command}`?" in text and f".venv/bin/turtlectl {command} --port " in text
            assert exit_code(err.value) == ExitCode.CANNOT_START


def test_no_router_to_join_is_unreachable_within_the_timeout():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]  # bound, not listening: nothing answers there
        started = time.monotonic()
        with pytest.raises(Unreachable, match=f"no router at tcp/127.0.0.1:{port} to join"):
            close_session(join_router(f"tcp/127.0.0.1:{port}", timeout=0.5))
    assert time.monotonic() - started < 3.0


def test_a_busy_port_names_the_commands_that_avoid_it():
    text = port_in_use(7447, "launch")
    assert "the port is already in use" in text
    assert '.venv/bin/turtlectl launch --port 7448 (or make run ARGS="--port 7448")' in text
    assert port_in_use(65535, "router").endswith(".venv/bin/turtlectl router --port 65534")


def test_the_port_suggested_instead_of_a_busy_one_is_free():
    """A review found `--port 7544` suggested while 7544 was taken too."""
    with socket.socket() as busy, socket.socket() as next_busy:
        busy.bind(("127.0.0.1", 0))
        port = busy.getsockname()[1]
        try:
            next_busy.bind(("127.0.0.1", port + 1))
        except OSError:
            pass  # already taken by someone else: just as good for this test
        suggested = free_port_near(port)
    assert suggested not in (port, port + 1)
