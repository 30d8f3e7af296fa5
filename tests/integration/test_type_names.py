"""Two packages' TurtleStatus in one system, as ROS names types by package: a user's node publishes
its own ``TurtleStatus`` (module ``capstone_msgs``, so ``capstone_msgs/TurtleStatus``) on
capstone/status beside the built-in status monitor's ``turtlectl/TurtleStatus`` on robot/status.
Both run; every tool names each by its full name (echo, list, interface), a short name that
both types have is refused naming both, and one recording holds both, each read back as its own
type."""

from __future__ import annotations

import json
import subprocess
import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.integration.harness import System, running_system, turtlectl
from turtlectl.cli.recording.reading import Recording
from turtlectl.messages.codec import type_name

pytestmark = pytest.mark.integration

CAPSTONE_MSGS = textwrap.dedent(
    '''
    from turtlectl import Message


    class TurtleStatus(Message, tag="TurtleStatus"):
        """The student's own status: how the lesson names it."""

        battery: float  # %: charge left
        mood: str = "fine"  # -: how the run goes
        laps: int = 0  # -: laps driven
        stamp: int = 0  # ns: when it was published
        seq: int = 0  # -: per-publisher count
    '''
)

REPORTER = textwrap.dedent(
    """
    import msgspec
    from capstone_msgs import TurtleStatus

    from turtlectl import Interface


    class Reporter:
        Params = msgspec.defstruct("ReporterParams", [])
        Interface = Interface(publishes=("capstone/status",))

        def __init__(self, node):
            pub = node.publisher("capstone/status", TurtleStatus)
            node.timer(0.1, lambda: pub.publish(TurtleStatus(battery=87.5, laps=3)))
    """
)

LAUNCH = """
[[node]]
name = "sim"
run = "sim"

[[node]]
name = "status_monitor"
run = "status_monitor"

[[node]]
name = "reporter"
run = "./reporter.py:Reporter"
"""

OURS = "capstone_msgs/TurtleStatus"
BUILTIN = "turtlectl/TurtleStatus"


@pytest.fixture(scope="module")
def system(tmp_path_factory) -> Iterator[System]:
    project = tmp_path_factory.mktemp("capstone")
    (project / "capstone_msgs.py").write_text(CAPSTONE_MSGS)
    (project / "reporter.py").write_text(REPORTER)
    (project / "launch.toml").write_text(LAUNCH)
    checked = subprocess.run(
        [*turtlectl(), "launch", "--check", str(project / "launch.toml")],
        cwd=project,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert checked.returncode == 0, checked.stdout + checked.stderr
    with running_system(project / "launch.toml", ready=("sim", "status_monitor", "reporter"), cwd=project) as system:
        yield system


def test_both_run_and_echo_names_each_by_its_full_name(system):
    builtin = system.run_cli("echo", "robot/status", "--once")
    ours = system.run_cli("echo", "capstone/status", "--once")
    assert builtin.returncode == 0 and ours.returncode == 0, builtin.stderr + ours.stderr
    assert builtin.stdout.startswith(f"# {BUILTIN}\n") and "vel_x:" in builtin.stdout, builtin.stdout
    assert ours.stdout.startswith(f"# {OURS}\n") and "mood: fine" in ours.stdout, ours.stdout
    assert json.loads(system.run_cli("echo", "robot/status", "--once", "--json").stdout)["type"] == BUILTIN
    line = json.loads(system.run_cli("echo", "capstone/status", "--once", "--json").stdout)
    assert line["type"] == OURS and line["laps"] == 3
    # the reporter started once and stays up: no crash loop
    assert system.output().count("reporter") and "Traceback" not in system.output(), system.output()


def test_list_shows_both_full_names(system):
    listed = system.run_cli("list")
    assert listed.returncode == 0, listed.stderr
    rows = {line.split()[0]: line for line in listed.stdout.splitlines() if line.strip()}
    assert OURS in rows.get("capstone/status", ""), listed.stdout
    assert BUILTIN in rows.get("robot/status", ""), listed.stdout
    assert "CONFLICT" not in listed.stdout, listed.stdout


def test_interface_show_gives_each_its_own_fields_and_refuses_the_short_name(system):
    ours = system.run_cli("interface", "show", OURS)
    assert ours.returncode == 0, ours.stderr
    assert ours.stdout.startswith(OURS) and "\nmood " in ours.stdout and "vel_x" not in ours.stdout, ours.stdout
    builtin = system.run_cli("interface", "show", BUILTIN)
    assert builtin.returncode == 0, builtin.stderr
    assert builtin.stdout.startswith(BUILTIN) and "\nvel_x " in builtin.stdout, builtin.stdout
    assert "mood" not in builtin.stdout, builtin.stdout
    short = system.run_cli("interface", "show", "TurtleStatus")
    assert short.returncode == 2 and OURS in short.stderr and BUILTIN in short.stderr, short
    assert len(short.stderr.strip().splitlines()) == 1, short.stderr
    listed = system.run_cli("interface", "list")
    assert OURS in listed.stdout and BUILTIN in listed.stdout, listed.stdout


def test_one_recording_holds_both_each_read_back_as_its_own_type(system, tmp_path: Path):
    path = tmp_path / "both.mcap"
    recorded = system.run_cli("record", "robot/status", "capstone/status", "-o", str(path), "--duration", "2")
    assert recorded.returncode == 0, recorded.stderr
    info = subprocess.run([*turtlectl(), "info", str(path)], capture_output=True, text=True, timeout=30)
    assert info.returncode == 0, info.stderr
    shown = {line.split()[0]: line.split()[1] for line in info.stdout.splitlines() if line.startswith("  ")}
    assert shown.get("robot/status") == BUILTIN and shown.get("capstone/status") == OURS, info.stdout
    recording = Recording(path)
    assert {t.key: t.type_name for t in recording.info().topics} == {"robot/status": BUILTIN, "capstone/status": OURS}
    messages = {r.key: r.message() for r in recording.records()}  # the last of each
    assert type_name(type(messages["robot/status"])) == BUILTIN and messages["robot/status"].vel_x is not None
    assert type_name(type(messages["capstone/status"])) == OURS
    assert messages["capstone/status"].laps == 3 and messages["capstone/status"].mood == "fine"


def test_topic_info_node_info_and_hz_name_each_in_full(system):
    topic = system.run_cli("topic", "info", "capstone/status")
    assert topic.returncode == 0 and OURS in topic.stdout, topic.stdout + topic.stderr
    assert BUILTIN in system.run_cli("topic", "info", "robot/status").stdout
    node = system.run_cli("node", "info", "reporter")
    assert node.returncode == 0 and OURS in node.stdout, node.stdout + node.stderr
    assert BUILTIN in system.run_cli("node", "info", "status_monitor").stdout
