"""The CLI's contract with nothing or something broken to talk to: exit codes and messages."""

from __future__ import annotations

import subprocess
import time

import pytest

from tests.integration.harness import free_port, running_system, turtlectl
from turtlectl import Client
from turtlectl.cli.tools import topics
from turtlectl.runtime.client import session as client
from turtlectl.runtime.client.errors import ExitCode, TurtlectlError, exit_code

pytestmark = pytest.mark.integration


def run(*args: str, timeout: float = 20.0) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*turtlectl(), *args], capture_output=True, text=True, timeout=timeout, stdin=subprocess.DEVNULL
    )


def test_the_installed_command_turns_a_bad_argument_into_one_line_and_exit_2():
    """The console script end to end, once; every argument check is tested in-process with
    CliRunner (tests/unit/cli/test_main.py)."""
    result = run("goto", "nan", "1", "0", "--connect", f"tcp/127.0.0.1:{free_port()}")
    assert (result.returncode, result.stderr) == (2, "turtlectl: error: x must be a finite number, got 'nan'\n")


def waited(call) -> tuple[TurtlectlError, float]:
    """The error a client call ends with and how long it waited, measured in this process:
    what the command controls, without the interpreter's start-up (0.4-0.7 s here, more on a
    slower machine), which no test of behaviour should time."""
    started = time.monotonic()
    with pytest.raises(TurtlectlError) as err:
        call()
    return err.value, time.monotonic() - started


def _goto(endpoint: str) -> None:
    """A goal to navigate_to from the Python client, as the command line's goto sends it."""
    with Client(endpoint) as python_client:
        python_client.goto(1, 1, 0)


def test_goto_with_nothing_running_exits_3():
    result = run("goto", "1", "1", "0", "--connect", f"tcp/127.0.0.1:{free_port()}")
    assert result.returncode == 3, result.stderr
    assert "no turtlectl system at" in result.stderr


def test_with_nothing_running_the_wait_is_under_3_seconds():
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    error, seconds = waited(lambda: _goto(endpoint))
    assert exit_code(error) == ExitCode.UNREACHABLE and "no turtlectl system at" in error.message
    assert seconds < 3.0, seconds  # nothing listens on the port: reported at once, not after OPEN_TIMEOUT


def test_echo_with_nothing_running_exits_3():
    result = run("echo", "robot/status", "--connect", f"tcp/127.0.0.1:{free_port()}")
    assert result.returncode == 3 and "no turtlectl system" in result.stderr


def test_connect_is_read_from_the_environment():
    port = free_port()
    result = subprocess.run(
        [*turtlectl(), "goto", "1", "1", "0"],
        capture_output=True,
        text=True,
        timeout=20,
        env={**__import__("os").environ, "TURTLECTL_CONNECT": f"tcp/127.0.0.1:{port}"},
    )
    assert result.returncode == 3 and f"tcp/127.0.0.1:{port}" in result.stderr


def test_malformed_launch_file_exits_2_with_the_key_path(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[[node]]\nname = "sim"\nrun = "sim"\n[node.params]\ncmd_timeout = "soon"\n')
    result = run("launch", str(bad), "--port", str(free_port()))
    assert result.returncode == 2
    assert f"{bad}: node[0] (sim).params.cmd_timeout must be a number (got " in result.stderr
    assert "router listening" not in result.stdout and "Traceback" not in result.stderr


def test_missing_launch_file_exits_2(tmp_path):
    result = run("launch", str(tmp_path / "none.toml"))
    assert result.returncode == 2 and "cannot read" in result.stderr


def test_help_documents_exit_codes():
    result = run("goto", "--help")
    assert result.returncode == 0 and "Example: turtlectl goto" in result.stdout
    assert "3 nothing to talk to" in " ".join(run("--help").stdout.split())


def test_goto_with_no_navigator_exits_3_within_3_seconds(tmp_path):
    only_sim = tmp_path / "sim_only.toml"
    only_sim.write_text('[[node]]\nname = "sim"\nrun = "sim"\n')
    with running_system(only_sim, ready=("sim",)) as system:
        result = system.run_cli("goto", "1", "1", "0")
        assert result.returncode == 3, result.stdout + result.stderr
        assert "nothing serves navigate_to" in result.stderr
        error, seconds = waited(lambda: _goto(system.endpoint))
        assert exit_code(error) == ExitCode.UNREACHABLE and "nothing serves navigate_to" in error.message
        assert seconds < 3.0, seconds


@pytest.mark.parametrize(
    "endpoint", ["tcp/127.0.0.1", "tcp/127.0.0.1:abc", "tcp/127.0.0.1:99999", "127.0.0.1:7447", "garbage"]
)
def test_a_malformed_endpoint_is_bad_input_at_once(endpoint):
    result = run("list", "--connect", endpoint)
    assert result.returncode == 2 and "write it as tcp/HOST:PORT" in result.stderr, result.stderr
    error, seconds = waited(lambda: topics.graph(endpoint, ""))
    assert exit_code(error) == ExitCode.BAD_INPUT
    assert seconds < client.OPEN_TIMEOUT / 2, seconds  # refused before any connection attempt


def test_domain_names_may_be_numbers_but_not_paths():
    assert run("--domain", "42", "list", "--connect", f"tcp/127.0.0.1:{free_port()}").returncode == 3
    bad = run("--domain", "a/b", "list")
    assert bad.returncode == 2 and "--domain 'a/b'" in bad.stderr


def test_pub_refuses_wildcards_and_internal_keys():
    for key in ("turtle1/*", "@turtlectl/node/sim/1", "**"):
        result = run("pub", key, '{"linear": 1}', "--type", "Twist", "--connect", f"tcp/127.0.0.1:{free_port()}")
        assert result.returncode == 2 and "one plain key" in result.stderr, (key, result.stderr)


def test_version_comes_from_the_package_metadata():
    result = run("--version")
    assert result.returncode == 0 and result.stdout == "turtlectl 0.1.0\n", result
