"""The command surface in this process (Typer's CliRunner, no binary started): every check of
what users type gives exit code 2 and its message before anything is sent or started; errors
become exit codes in ``main`` only; ``turtlectl --help`` imports nothing heavy; --domain and
--connect work before and after the command."""

from __future__ import annotations

import re
import signal
import socket
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from turtlectl.cli.main import app, error_line, main
from turtlectl.cli.system.launchfile import PACKAGED_LAUNCH
from turtlectl.runtime.client.errors import BadInput, ExitCode, Interrupted, TurtlectlError, exit_code
from turtlectl.runtime.endpoint import CONNECT_ENV, DOMAIN_ENV

FLEET = Path(__file__).resolve().parents[3] / "examples" / "fleet" / "launch.toml"

HEAVY = [
    "numpy",
    "curses",
    "turtlectl.cli.tools.view",
    "turtlectl.runtime.client.session",
    "turtlectl.runtime.client.services",
    "turtlectl.cli.tools.topics",
    "turtlectl.cli.system.launchfile",
    "turtlectl.cli.system.supervisor.manager",
    "turtlectl.cli.system.supervisor.router",
    "turtlectl.runtime.node",
    "turtlectl.runtime.lifecycle",
    "turtlectl.nodes.kinds",
    "msgspec",  # the message types would cost --help 25 ms; the commands that send one import them
    "cyclonedds",  # the ROS 2 bridge's DDS side (~0.35 s): its node process imports it, nothing else
]


ENDPOINT_ERROR = (
    "turtlectl: error: 'garbage' is not an endpoint: write it as tcp/HOST:PORT (from --connect or TURTLECTL_CONNECT)"
)


DOMAIN_ERROR = "turtlectl: error: --domain 'a/b': use letters, digits, _ and - (like lab1 or 42)"


@pytest.fixture(autouse=True)
def plain_environment(monkeypatch, tmp_path):
    """No domain or endpoint from the environment, no ./launch.toml: the packaged one is used.
    (The commands set TURTLECTL_DOMAIN/CONNECT for the sessions they open; monkeypatch undoes it.)"""
    for name in (DOMAIN_ENV, CONNECT_ENV, "TURTLECTL_LOG_DIR"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.chdir(tmp_path)


def sessions_opened(monkeypatch) -> list[str]:
    """The domain of each client session a command opens from now on (none opens: each raises
    NoSystem, as with nothing listening at its endpoint)."""
    from turtlectl.cli.tools import topics
    from turtlectl.runtime.client import api, services, session

    domains: list[str] = []

    def opened(connect, domain=None, role=None):
        domains.append(domain)
        raise session.NoSystem(connect)

    for module in (session, topics, api, services):
        monkeypatch.setattr(module, "client_session", opened)
    return domains


def invoke(*argv: str) -> tuple[int, str]:
    """The exit code and what the user reads for ``turtlectl ARGV``: an error of ours as ``main``
    turns it into both (the one table, the one wording), Typer's own as Click prints it."""
    result = CliRunner().invoke(app, list(argv))
    if isinstance(result.exception, TurtlectlError):
        return int(exit_code(result.exception)), error_line(result.exception)
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return result.exit_code, result.output


def bad_input(*argv: str) -> str:
    code, text = invoke(*argv)
    assert code == ExitCode.BAD_INPUT, (code, text)
    return text


@pytest.mark.parametrize("command", ["goto", "teleport"])
@pytest.mark.parametrize(
    "xyz, message",
    [
        (("nan", "1", "0"), "x must be a finite number, got 'nan'"),
        (("1", "inf", "0"), "y must be a finite number, got 'inf'"),
        (("1", "2", "-infinity"), "theta must be a finite number, got '-infinity'"),
        (("1", "2", "north"), "theta must be a number, got 'north'"),
        (("one", "2", "3"), "x must be a number, got 'one'"),
        (("1_0", "2", "3"), "x must be a number, got '1_0'"),
        (("", "2", "3"), "x must be a number, got ''"),
    ],
)
def test_coordinates_must_be_finite_numbers(command, xyz, message):
    assert bad_input(command, *xyz, "--connect", "tcp/127.0.0.1:1") == f"turtlectl: error: {message}"


@pytest.mark.parametrize("command", ["goto", "teleport"])
def test_negative_coordinates_are_numbers_not_options(command):
    # they pass the number checks and reach the next one: the endpoint
    assert bad_input(command, "-1", "-2.5", "-90", "--connect", "garbage") == ENDPOINT_ERROR


def test_a_missing_coordinate_is_a_usage_error():
    assert "Missing argument 'THETA'" in bad_input("goto", "1", "2")


@pytest.mark.parametrize(
    "argv, option",
    [
        (("goto", "1", "1", "0", "--timeout", "0"), "--timeout"),
        (("goto", "1", "1", "0", "--timeout", "soon"), "--timeout"),
        (("call", "navigate_to", "--timeout", "0.05"), "--timeout"),
        (("echo", "robot/status", "--count", "0"), "--count"),
        (("echo", "robot/status", "--count", "two"), "--count"),
        (("echo", "robot/status", "--timeout", "0"), "--timeout"),
        (("hz", "robot/status", "--window", "1"), "--window"),
        (("hz", "robot/status", "--duration", "0.1"), "--duration"),
        (("pub", "turtle1/cmd_vel", "{}", "--rate", "0"), "--rate"),
        (("pub", "turtle1/cmd_vel", "{}", "--times", "0"), "--times"),
        (("launch", "--port", "0"), "--port"),
        (("launch", "--port", "65536"), "--port"),
        (("router", "--port", "0"), "--port"),
        (("router", "--port", "http"), "--port"),
    ],
)
def test_out_of_range_or_not_a_number_is_a_usage_error(argv, option):
    assert f"Invalid value for '{option}'" in bad_input(*argv)


def test_echo_json_and_csv_do_not_go_together():
    text = bad_input("echo", "robot/status", "--json", "--csv", "--connect", "tcp/127.0.0.1:1")
    assert text == "turtlectl: error: --json and --csv do not go together"


def test_echo_once_and_count_do_not_go_together():
    text = bad_input("echo", "robot/status", "--once", "--count", "2", "--connect", "tcp/127.0.0.1:1")
    assert text == "turtlectl: error: --once and --count do not go together"


@pytest.mark.parametrize("extra", [("--rate", "5"), ("--times", "2"), ("--rate", "5", "--times", "2")])
def test_pub_once_does_not_go_with_rate_or_times(extra):
    text = bad_input("pub", "turtle1/cmd_vel", "{}", "--once", *extra, "--connect", "tcp/127.0.0.1:1")
    assert text == "turtlectl: error: --once does not go with --rate or --times"


@pytest.mark.parametrize(
    "argv",
    [
        ("--domain", "a/b", "list"),
        ("list", "--domain", "a/b"),
        ("goto", "1", "1", "0", "--domain", "a/b"),
        ("launch", "--check", "--domain", "a/b"),
        ("--domain", "a b", "list"),
    ],
)
def test_a_domain_is_one_key_chunk(argv):
    expected = DOMAIN_ERROR.replace("'a/b'", repr(argv[argv.index("--domain") + 1]))
    assert bad_input(*argv) == expected


def test_a_domain_from_the_environment_is_checked_too(monkeypatch):
    monkeypatch.setenv(DOMAIN_ENV, "a/b")
    assert bad_input("list") == DOMAIN_ERROR


@pytest.mark.parametrize("value", ["abc", "0.1", "61", "nan"])
def test_a_bad_peer_timeout_stops_every_command_before_it_starts(value, monkeypatch):
    monkeypatch.setenv("TURTLECTL_PEER_TIMEOUT", value)
    said = f"turtlectl: error: TURTLECTL_PEER_TIMEOUT={value!r}: give seconds from 0.5 to 60"
    assert bad_input("list").strip() == said
    assert bad_input("launch", "--check").strip() == said


@pytest.mark.parametrize(
    "argv",
    [
        ("list", "--connect", "garbage"),
        ("--connect", "garbage", "list"),
        ("cancel", "--connect", "garbage"),
        ("reset", "--connect", "garbage"),
        ("goto", "1", "1", "0", "--connect", "garbage"),
        ("echo", "robot/status", "--connect", "garbage"),
        ("hz", "robot/status", "--connect", "garbage"),
        ("pub", "turtle1/cmd_vel", "{}", "--connect", "garbage"),
        ("call", "navigate_to/cancel", "--connect", "garbage"),
        ("view", "--connect", "garbage"),
        ("run", "sim", "--connect", "garbage"),
        ("launch", "--connect", "garbage"),
    ],
)
def test_an_endpoint_is_protocol_host_port(argv):
    assert bad_input(*argv) == ENDPOINT_ERROR


def test_an_endpoint_from_the_environment_is_checked_too(monkeypatch):
    monkeypatch.setenv(CONNECT_ENV, "garbage")
    assert bad_input("list") == ENDPOINT_ERROR


@pytest.mark.parametrize("command", ["launch", "router"])
@pytest.mark.parametrize("address", ["localhost", "127.0.0.1:7447", "300.1.1.1", ""])
def test_listen_takes_an_ip_address(command, address):
    assert bad_input(command, "--listen", address) == f"turtlectl: error: --listen {address!r} is not an IP address"


@pytest.mark.parametrize(
    "argv",
    [
        ("echo", "robot//status"),
        ("hz", "robot/status", "a//b"),
        ("call", "a//b"),
    ],
)
def test_a_key_must_be_a_key_expression(argv):
    assert "is not a valid key expression (like robot/status or turtle1/*)" in bad_input(
        *argv, "--connect", "tcp/127.0.0.1:1"
    )


@pytest.mark.parametrize("key", ["turtle1/*", "@turtlectl/node/sim/1", "**"])
def test_pub_refuses_wildcards_and_internal_keys(key):
    text = bad_input("pub", key, '{"linear": 1}', "--type", "Twist", "--connect", "tcp/127.0.0.1:1")
    assert text == f"turtlectl: error: {key!r}: publish on one plain key, without wildcards or '@'"


@pytest.mark.parametrize(
    "argv, message",
    [
        (
            ("pub", "turtle1/cmd_vel", '{"linear": "x"}'),
            "not a valid turtlectl/Twist: linear: Expected `float`, got `str`",
        ),
        (("pub", "turtle1/cmd_vel", "{"), "not valid JSON: "),
        (
            ("pub", "turtle1/cmd_vel", "{}", "--type", "Pose"),
            "turtle1/cmd_vel carries turtlectl/Twist, not turtlectl/Pose",
        ),
        (("pub", "some/key", "{}"), "no known message type for 'some/key': give one with --type"),
        (("pub", "some/key", "{}", "--type", "Nope"), "unknown message type 'Nope' (known: "),
        (("call", "turtle1/teleport_absolute", '{"x": 1}'), "missing required field `y`"),
        (
            ("call", "navigate_to/cancel", "{}", "--type", "Pose"),
            "navigate_to/cancel takes turtlectl/Cancel, not turtlectl/Pose",
        ),
        (("call", "any/key", "{"), "not valid JSON: "),
    ],
)
def test_a_payload_is_checked_before_anything_is_sent(argv, message):
    assert message in bad_input(*argv, "--connect", "tcp/127.0.0.1:1")


def test_launch_check_prints_the_plan_and_starts_nothing():
    code, text = invoke("launch", "--check", "--set", "navigator.goal_timeout=60")
    assert code == ExitCode.OK and text.startswith(f"{PACKAGED_LAUNCH}: valid\n") and '"goal_timeout":60' in text


@pytest.mark.parametrize(
    "argv, message",
    [
        (("--set", "navigator"), "--set 'navigator': write it as NODE.PARAM=VALUE or TABLE.KEY=VALUE"),
        (("--set", "navigator.goal_timeot=3"), "--set navigator.goal_timeot: unknown key; did you mean goal_timeout?"),
        (("--set", "world.size=-1"), "--set world.size must be > 0"),
        (("--set", "nosuch.x=1"), "--set 'nosuch.x=1': no node or table named 'nosuch'"),
        (("--only", "nosuch"), "--only nosuch: no node named 'nosuch'"),
        (("--exclude", "nosuch"), "--exclude nosuch: no node named 'nosuch'"),
        (
            (
                "--exclude",
                "sim",
                "--exclude",
                "navigator",
                "--exclude",
                "status_monitor",
                "--exclude",
                "obstacle_detector",
            ),
            "--only/--exclude leave no node to run",
        ),
    ],
)
def test_launch_options_are_validated_like_the_file(argv, message):
    assert message in bad_input("launch", "--check", *argv)


def test_a_launch_file_that_cannot_be_read_is_bad_input(tmp_path):
    missing = tmp_path / "none.toml"
    assert bad_input("launch", str(missing)).startswith(f"turtlectl: error: {missing}: cannot read: ")


def test_a_malformed_launch_file_names_the_key_path(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[[node]]\nname = "sim"\nrun = "sim"\n[node.params]\ncmd_timeout = "soon"\n')
    assert bad_input("launch", str(bad)) == (
        f'turtlectl: error: {bad}: node[0] (sim).params.cmd_timeout must be a number (got "soon")'
    )


@pytest.mark.parametrize(
    "argv, message",
    [
        (("nosuch",), f"{PACKAGED_LAUNCH}: no node named 'nosuch'"),
        (("navigator", "-p", "goal_timeout=0"), "--param navigator.goal_timeout must be >= 0.1"),
        (("navigator", "-p", "goal_timeout"), "--param 'goal_timeout': write it as KEY=VALUE"),
        (("navigator", "--file", "none.toml"), "none.toml: cannot read: "),
        # a file without its class (a new user's first try): not taken for a launch-file name
        (("./patrol.py",), "./patrol.py names a file: add its node class, as ./patrol.py:ClassName"),
        (("myrobot/patrol.py",), "myrobot/patrol.py names a file: add its node class"),
        # a namespaced node of a launch file is a name, not a file (not "turtle2/navigator names a file")
        (("turtle2/nav", "--file", str(FLEET)), "no node named 'turtle2/nav'; did you mean turtle2/navigator?"),
    ],
)
def test_run_checks_the_node_and_its_overrides_before_it_starts(argv, message):
    assert message in bad_input("run", *argv)


def test_main_prints_the_error_and_exits_with_its_code(monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", ["turtlectl", "echo", "robot/status", "--json", "--csv"])
    monkeypatch.setattr(sys, "unraisablehook", sys.unraisablehook)
    previous = signal.getsignal(signal.SIGINT)
    try:
        with pytest.raises(SystemExit) as ended:
            main()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert ended.value.code == ExitCode.BAD_INPUT
    assert capsys.readouterr().err == "turtlectl: error: --json and --csv do not go together\n"


def test_help_lists_the_commands_and_the_exit_codes():
    code, text = invoke("--help")
    assert code == ExitCode.OK and "goto" in text and "3 nothing to talk to" in " ".join(text.split())


def test_importing_the_command_line_loads_nothing_heavy():
    """`turtlectl --help` stays quick: numpy, curses, sessions, launch files and the supervisor
    are imported by the commands that use them."""
    code = f"import turtlectl.cli.main, sys; print([m for m in {HEAVY!r} if m in sys.modules])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_importing_the_command_line_does_not_import_numpy():
    code = "import turtlectl.cli.main, sys; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"


@pytest.mark.parametrize(
    "args",
    [
        ["list", "--domain", "lab9", "--connect", "tcp/127.0.0.1:1"],
        ["--domain", "lab9", "list", "--connect", "tcp/127.0.0.1:1"],
        ["--domain", "lab9", "--connect", "tcp/127.0.0.1:1", "list"],
        ["goto", "1", "1", "0", "--domain", "lab9", "--connect", "tcp/127.0.0.1:1"],
    ],
)
def test_domain_and_connect_work_before_and_after_the_command(args, monkeypatch):
    """`turtlectl goto 5 5 0 --domain lab1` (as a hint tells the user to add --domain) and
    `turtlectl --connect ... list` are taken, not refused with "unexpected extra argument"."""
    monkeypatch.delenv(DOMAIN_ENV, raising=False)
    monkeypatch.delenv(CONNECT_ENV, raising=False)
    domains = sessions_opened(monkeypatch)
    result = CliRunner().invoke(app, args)
    assert isinstance(result.exception, TurtlectlError), result.output  # it ran: nothing listens on port 1
    assert exit_code(result.exception) == ExitCode.UNREACHABLE and "tcp/127.0.0.1:1" in result.exception.message
    assert domains == ["lab9"]  # the command's session, in the domain given before or after it


def test_a_bad_domain_after_the_command_is_bad_input(monkeypatch):
    monkeypatch.delenv(DOMAIN_ENV, raising=False)
    result = CliRunner().invoke(app, ["list", "--domain", "a/b"])
    assert isinstance(result.exception, TurtlectlError) and exit_code(result.exception) == ExitCode.BAD_INPUT


def test_connect_before_launch_joins_that_router_as_after_it(tmp_path):
    """`turtlectl --connect E launch` joins E rather than run a router of its own."""
    with socket.socket() as busy, socket.socket() as probe:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        probe.bind(("127.0.0.1", 0))
        dead = f"tcp/127.0.0.1:{probe.getsockname()[1]}"  # bound, not listening: nobody answers there
        port = str(busy.getsockname()[1])  # a router of its own would fail on this busy port (exit 4)
        for argv in (["--connect", dead, "launch"], ["launch", "--connect", dead]):
            code, text = invoke(*argv, "--port", port, "--log-dir", str(tmp_path))
            assert (code, text) == (ExitCode.UNREACHABLE, f"turtlectl: error: no router at {dead} to join"), argv


def test_connect_before_router_is_refused():
    assert "router takes no --connect" in bad_input("--connect", "tcp/127.0.0.1:7447", "router")


def test_a_ctrl_c_is_reported_as_what_happened_not_as_an_error():
    """Ctrl-C on goto does not read 'turtlectl: error: interrupted: …'."""
    assert error_line(Interrupted("interrupted: the navigator cancels the goal")) == (
        "turtlectl: interrupted: the navigator cancels the goal"
    )
    assert error_line(BadInput("x")) == "turtlectl: error: x"


def test_record_into_an_existing_file_is_refused_before_it_says_it_records(tmp_path):
    """The refusal comes first: not "recording ** into a.mcap" before it (nor, with no router,
    "no turtlectl system" and exit 3 when the file is the problem)."""
    (tmp_path / "a.mcap").write_bytes(b"kept")
    result = CliRunner().invoke(app, ["record", "-a", "-o", "a.mcap", "--connect", "tcp/127.0.0.1:9"])
    assert isinstance(result.exception, BadInput), result.output
    assert error_line(result.exception) == "turtlectl: error: a.mcap already exists: choose another name with -o"
    assert "recording" not in result.output and (tmp_path / "a.mcap").read_bytes() == b"kept"


def test_play_from_past_the_end_says_how_long_the_recording_is(tmp_path):
    from turtlectl.cli.recording.bag import BagWriter
    from turtlectl.messages import Pose, encode, encoding_for

    writer = BagWriter(tmp_path / "run.mcap")
    for i in range(63):  # 0.992 s
        writer.add("turtle1/pose", encoding_for(Pose), encode(Pose(x=1, y=1, theta=0, seq=i)), i * 16_000_000)
    writer.close()
    text = bad_input("play", "run.mcap", "--start-offset", "100", "--connect", "tcp/127.0.0.1:9")
    assert text == "turtlectl: error: --start-offset 100 s is past the end of run.mcap (0.992 s long)"


@pytest.mark.parametrize(
    "argv, option",
    [
        (("play", "run.mcap", "--rate", "nan"), "--rate"),
        (("play", "run.mcap", "--start-offset", "nan"), "--start-offset"),
        (("record", "-a", "--duration", "nan"), "--duration"),
    ],
)
def test_nan_is_no_rate_offset_or_duration(argv, option):
    """`play --rate nan` and `record --duration nan` are refused (Typer's ranges let NaN through:
    play would publish nothing and never end, record would record nothing with exit 0)."""
    assert (
        bad_input(*argv, "--connect", "tcp/127.0.0.1:9")
        == f"turtlectl: error: {option} must be a finite number, got nan"
    )


def _leaves(command, path=()):
    """Every runnable command under ``command``, with its path (``param set``)."""
    subs = getattr(command, "commands", None)
    if not subs:
        yield path, command
        return
    for name, sub in subs.items():
        yield from _leaves(sub, (*path, name))


def test_help_groups_the_commands_and_every_command_has_an_example():
    """`turtlectl --help` stays readable as it grows; each command shows how it is used."""
    import typer.main

    from turtlectl.cli.main import COMMAND_GROUPS

    code, text = invoke("--help")
    assert code == ExitCode.OK
    sections = [line[:-1] for line in text.splitlines() if line.endswith(":") and not line.startswith(" ")]
    assert sections[-len(COMMAND_GROUPS) :] == list(COMMAND_GROUPS)
    root = typer.main.get_command(app)
    grouped = [name for names in COMMAND_GROUPS.values() for name in names]
    assert sorted(grouped) == sorted(root.commands), "every command in exactly one group"
    for path, _ in _leaves(root):
        code, help_text = invoke(*path, "--help")
        assert code == 0 and "Example: turtlectl " + " ".join(path) in " ".join(help_text.split()), path


@pytest.mark.parametrize("argv", [("launch", "--log-level", "loud"), ("run", "navigator", "--log-level", "loud")])
def test_a_log_level_is_one_of_the_four(argv):
    assert bad_input(*argv) == "turtlectl: error: unknown log level 'loud' (known: DEBUG, INFO, WARNING, ERROR)"


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (("param", "dump", "**"), "**"),
        (("param", "list", "a/*"), "a/*"),
        (("param", "describe", "*", "rate"), "*"),
        (("node", "info", ""), ""),
    ],
)
def test_a_node_name_is_a_name_not_a_key_expression(argv, name):
    """Where one node is meant (param list, describe, dump), a glob is refused: it would answer for one node only."""
    assert bad_input(*argv).startswith(f"turtlectl: error: {name!r} is not a node name: letters, digits, _ and -")


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (("param", "set", "nav igator", "rate", "1"), "nav igator"),
        (("param", "get", "a.b", "rate"), "a.b"),
        (("log-level", "turtle2/**x$", "DEBUG"), "turtle2/**x$"),
    ],
)
def test_a_node_selector_is_a_name_namespace_turtle_or_glob(argv, name):
    """`log-level`, `param get` and `param set` take several nodes (a glob, a namespace, a turtle), as `log --node` does."""
    assert bad_input(*argv).startswith(f"turtlectl: error: {name!r} is not a node, namespace, turtle or glob")


def test_a_node_name_may_have_ros_s_slash_a_namespace_or_the_domain_list_shows(monkeypatch):
    """`/navigator` is navigator; `turtle2/navigator` navigator in namespace turtle2 (a
    namespace's nodes); `lab1:navigator` is navigator in domain lab1 (as `list` shows it; the
    slash is the namespace's)."""
    from turtlectl.cli import args

    assert args.node_name("/navigator") == ("", "navigator")
    assert args.node_name("turtle2/navigator") == ("", "turtle2/navigator")
    assert args.node_name("/turtle2/navigator") == ("", "turtle2/navigator")
    assert args.node_name("lab1:navigator") == ("lab1", "navigator")
    assert args.node_name("lab1:turtle2/navigator") == ("lab1", "turtle2/navigator")
    code, text = invoke("--domain", "lab2", "param", "get", "lab1:navigator", "rate")
    assert code == ExitCode.BAD_INPUT and "node 'lab1:navigator' is in domain 'lab1', not in --domain 'lab2'" in text
    domains = sessions_opened(monkeypatch)
    code, text = invoke("param", "get", "lab1:navigator", "rate", "--connect", "tcp/127.0.0.1:1")
    assert code == ExitCode.UNREACHABLE and domains == ["lab1"]  # the command's session, in the node's domain


def test_warn_is_warning_as_ros_spells_it():
    from turtlectl.cli import args

    assert args.log_level("warn") == "WARNING" and args.log_level(" Error ") == "ERROR"


def test_teleop_without_a_terminal_is_bad_input_before_any_router_is_asked():
    """Bad input is exit 2 even with no router (exit 3 would hide the input that cannot work)."""
    assert bad_input("teleop", "--connect", "tcp/127.0.0.1:1").endswith("its input is not one (run it in a terminal)")


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ("launch", "--listen", "10.0.0.1"),
            "--listen 10.0.0.1 reaches beyond this machine, and without logins anyone",
        ),
        (("router", "--listen", "10.0.0.1"), "--listen 10.0.0.1 reaches beyond this machine"),
        (
            ("launch", "--secure", "--listen", "10.0.0.1"),
            "--secure --listen 10.0.0.1: logins would cross the network in clear",
        ),
        (("launch", "--secure", "--connect", "tcp/127.0.0.1:7447"), "--secure runs a router of its own"),
        (("launch", "--secure", "--insecure"), "--secure and --insecure do not go together"),
    ],
)
def test_a_router_beyond_loopback_needs_insecure_to_insist(argv, message):
    """Nothing listens beyond loopback unless asked, and then with what it means said."""
    assert bad_input(*argv).startswith("turtlectl: error: " + message)


def test_insecure_lets_a_launch_listen_on_a_network_address():
    code, text = invoke("launch", "--listen", "10.0.0.1", "--insecure", "--check")
    assert code == ExitCode.OK, text


def test_secure_beyond_loopback_needs_tls_and_tls_needs_its_certificates(tmp_path):
    assert bad_input("launch", "--secure", "--listen", "10.0.0.1").endswith(
        "add --tls DIR, with the certificates of `turtlectl certs DIR --host HOST`"
    )
    assert bad_input("launch", "--tls", str(tmp_path)).startswith("turtlectl: error: --tls goes with --secure")
    assert bad_input("launch", "--secure", "--tls", str(tmp_path)) == (
        f"turtlectl: error: --tls {tmp_path}: no ca.pem, router.pem, router.key, client.pem, client.key there "
        f"(make them with `turtlectl certs {tmp_path}`)"
    )
    previous = signal.getsignal(signal.SIGINT)
    try:
        code, text = invoke("certs", str(tmp_path / "tls"), "--host", "10.0.0.1")  # prints its result: Ctrl-C ignored
    finally:
        signal.signal(signal.SIGINT, previous)
    assert code == ExitCode.OK and "router.pem" in text, text
    code, text = invoke("launch", "--secure", "--tls", str(tmp_path / "tls"), "--listen", "10.0.0.1", "--check")
    assert code == ExitCode.OK, text


def test_usage_shows_an_argument_that_takes_several_as_name_dots():
    """`hz`'s usage says it takes several topics, not `{TOPIC}`."""
    import typer.main

    root = typer.main.get_command(app)
    for path, command in _leaves(root):
        usage = invoke(*path, "--help")[1].splitlines()[0]
        for param in command.params:
            if param.param_type_name == "argument" and param.nargs == -1:
                name = (param.metavar or param.name.upper()).strip("[]{}.")
                assert re.search(rf"\b{name}\]?\.\.\.", usage), usage


@pytest.mark.parametrize("command", [("goto", "1", "1", "0"), ("cancel",), ("echo", "robot/status"), ("hz", "pose")])
def test_turtle_is_a_turtles_name(command):
    """--turtle names the turtle whose nodes a command reaches (their namespace)."""
    assert bad_input(*command, "--turtle", "a b") == (
        "turtlectl: error: --turtle 'a b': a turtle's name, letters, digits, _ and - (like turtle2)"
    )


def test_a_turtles_namespace_is_its_name_and_turtle1s_the_running_systems():
    from turtlectl.messages.keys import resolve, turtle_namespace
    from turtlectl.runtime.client import checks

    assert checks.turtle_name("turtle1") == "turtle1" and checks.turtle_name("") == ""
    assert checks.turtle_name("/turtle2") == "turtle2"
    # turtle1's nodes outside any namespace (the default launch file), or in turtle1 as any turtle's
    assert turtle_namespace("turtle1") == "" and turtle_namespace("") == ""
    assert turtle_namespace("turtle1", {"turtle1", "turtle2"}) == "turtle1"
    assert turtle_namespace("turtle2") == "turtle2" and turtle_namespace("turtle2", {"turtle1"}) == "turtle2"
    assert (
        resolve("navigate_to", "turtle1") == "turtle1/navigate_to"
        and resolve("turtle1/pose", "turtle1") == "turtle1/pose"
    )
    assert resolve("navigate_to", turtle_namespace("turtle2")) == "turtle2/navigate_to"
    assert resolve("turtle1/pose", turtle_namespace("turtle2")) == "turtle2/pose"
    assert resolve("reset", "turtle2") == "reset" and resolve("/chatter", "turtle2") == "chatter"
    assert resolve("turtlectl/world", "turtle2") == "turtlectl/world"


def test_launch_check_counts_one_obstacle_in_the_singular(tmp_path):
    (tmp_path / "one.toml").write_text(
        '[world]\nsize = 11.0\nobstacles = [{ x = 3.0, y = 3.0, radius = 0.5 }]\n\n[[node]]\nname = "sim"\nrun = "sim"\n'
    )
    code, text = invoke("launch", "--check", str(tmp_path / "one.toml"))
    assert code == ExitCode.OK and "world: 11 m square, 1 obstacle; (3, 3) r 0.5\n" in text, text


def test_connect_after_the_command_wins_over_connect_before_it(monkeypatch):
    monkeypatch.delenv(CONNECT_ENV, raising=False)
    result = CliRunner().invoke(app, ["--connect", "tcp/127.0.0.1:2", "list", "--connect", "tcp/127.0.0.1:1"])
    assert isinstance(result.exception, TurtlectlError), result.output
    assert "tcp/127.0.0.1:1" in result.exception.message and "127.0.0.1:2" not in result.exception.message


def test_help_imports_no_second_click():
    """typer carries its own click: importing click itself as well costs `--help` ~15 ms."""
    code = "import sys; sys.argv = ['turtlectl', '--help']\nfrom turtlectl.cli.main import main\ntry:\n    main()\nexcept SystemExit:\n    pass\nprint('click' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip().splitlines()[-1] == "False"
