"""cli.system.supervisor.router: the one way a router is opened or joined, and what its failures say."""

from __future__ import annotations

import socket
import time

import pytest

from turtlectl.cli.system.supervisor.router import (
    MAKE_RUN_ENV,
    MAKE_WEB_ENV,
    free_port_near,
    invoked_as,
    join_router,
    open_router,
    port_in_use,
    retyped,
)
from turtlectl.runtime.client.errors import CannotStart, ExitCode, Unreachable, exit_code
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
            assert f"another `turtlectl {command}`?" in text and f"turtlectl {command} --port " in text
            assert exit_code(err.value) == ExitCode.CANNOT_START


def test_no_router_to_join_is_unreachable_within_the_timeout():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]  # bound, not listening: nothing answers there
        started = time.monotonic()
        with pytest.raises(Unreachable, match=f"no router at tcp/127.0.0.1:{port} to join"):
            close_session(join_router(f"tcp/127.0.0.1:{port}", timeout=0.5))
    assert time.monotonic() - started < 3.0


def test_a_busy_port_names_the_command_that_avoids_it():
    text = port_in_use(7447, "launch")
    assert "the port is already in use" in text
    assert text.endswith("choose another: turtlectl launch --port 7448")
    assert port_in_use(65535, "router").endswith("turtlectl router --port 65534")


def test_the_command_suggested_is_the_one_typed_with_its_launch_file_and_arguments(tmp_path):
    argv = ["turtlectl", "--domain", "lab", "launch", "my fleet.toml", "--arg", "speed=2", "--port", "7447"]
    assert (
        retyped(argv, "launch", 7448, {}) == "turtlectl --domain lab launch 'my fleet.toml' --arg speed=2 --port 7448"
    )
    argv = ["./bin/turtlectl", "launch", "fleet.toml", "--port=7447", "--only", "sim"]
    assert retyped(argv, "launch", 7450, {}) == "./bin/turtlectl launch fleet.toml --port=7450 --only sim"
    assert (
        retyped(["turtlectl", "launch", "fleet.toml"], "launch", 7448, {}) == "turtlectl launch fleet.toml --port 7448"
    )
    assert retyped(["turtlectl", "router"], "router", 7448, {}) == "turtlectl router --port 7448"
    # another process's command line (a test's, an embedding's): the plain command
    assert retyped(["pytest", "-q"], "launch", 7448, {}) == "turtlectl launch --port 7448"


def test_under_make_run_the_suggestion_is_make_run_with_the_same_args():
    argv = [".venv/bin/turtlectl", "launch", "examples/fleet/launch.toml", "--port", "7447"]
    suggestion = retyped(argv, "launch", 7448, {MAKE_RUN_ENV: "1"})
    assert suggestion == "make run ARGS='examples/fleet/launch.toml --port 7448'"
    # the page make run serves (WEB) is make's own: not in the ARGS to type; a --web of the user's ARGS is
    argv = [".venv/bin/turtlectl", "launch", "--port", "7447", "--web", "8080"]
    assert retyped(argv, "launch", 7448, {MAKE_RUN_ENV: "1", MAKE_WEB_ENV: "8080"}) == "make run ARGS='--port 7448'"
    assert (
        retyped(argv, "launch", 7448, {MAKE_RUN_ENV: "1", MAKE_WEB_ENV: ""}) == "make run ARGS='--port 7448 --web 8080'"
    )


def test_a_program_found_on_path_is_named_as_typed_and_any_other_by_its_path(tmp_path):
    program = tmp_path / "turtlectl"
    program.write_text("#!/bin/sh\n")
    program.chmod(0o755)
    assert invoked_as(str(program), path=str(tmp_path)) == ["turtlectl"]  # the shell gave its full path
    assert invoked_as(str(program), path="/nonexistent") == [str(program)]
    assert invoked_as(".venv/bin/turtlectl", path="/nonexistent") == [".venv/bin/turtlectl"]
    assert invoked_as("/x/turtlectl/cli/__main__.py") == ["python", "-m", "turtlectl.cli"]


def test_the_port_suggested_instead_of_a_busy_one_is_free():
    """A port suggested is free (not `--port 7544` while 7544 is taken too)."""
    with socket.socket() as busy, socket.socket() as next_busy:
        busy.bind(("127.0.0.1", 0))
        port = busy.getsockname()[1]
        try:
            next_busy.bind(("127.0.0.1", port + 1))
        except OSError:
            pass  # already taken by someone else: just as good for this test
        suggested = free_port_near(port)
    assert suggested not in (port, port + 1)
