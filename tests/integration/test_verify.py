"""`turtlectl verify` checks a system against a specification file: the capstone's
passes on the default system it launches (criterion 5 shortened); each kind of criterion fails,
with its reason, on a system made to miss it (a status monitor slowed with `param set`; a user's
own navigator that takes 3 s, misreports its time and logs errors; a key nobody publishes; a
payload that is not its type); JSON and JUnit parse; no system is exit 3."""

from __future__ import annotations

import json
import re
import textwrap
import threading
from xml.etree import ElementTree as ET

import pytest

from tests.integration.harness import ROOT, free_port, running_system, turtlectl

pytestmark = pytest.mark.integration

PERIOD_ONLY = """intent = "status every 100 ms"
[[criterion]]
check = "period"
key = "robot/status"
period_ms = 100
tolerance_ms = 10
samples = 20
"""


def test_the_capstone_spec_passes_on_the_default_system(tmp_path):
    import subprocess

    junit = tmp_path / "verify.xml"
    done = subprocess.run(
        [
            *turtlectl(),
            "verify",
            str(ROOT / "docs" / "capstone.toml"),
            "--launch",
            str(ROOT / "launch.toml"),
            "--short",
            "5",
            "--junit",
            str(junit),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert "measuring: 2. status messages every 100 ms" in done.stderr
    assert "5 min alive, same process, no ERROR records, while goals are driven; shortened to 5 s (--short)" in (
        done.stdout
    ), done.stdout
    assert re.search(r"; [1-9]\d* goals? driven: ", done.stdout), done.stdout  # criterion 5 drives goals meanwhile
    rows = {line.split("  ")[0]: line for line in done.stdout.splitlines()}
    assert rows["4. the launch file starts every node with its parameters"].endswith("ok"), done.stdout
    assert "4 nodes' parameters read, 0 differ" in done.stdout
    cases = ET.parse(junit).getroot().findall("testsuite/testcase")
    assert len(cases) == 10 and cases[-1].get("name", "").startswith("7. the status message"), done.stdout
    # Every check holds; criterion 1's 2 s (1.76 s typical here) once measured 2.83 s on a loaded CI
    # machine: a time only, then, with the goal reached (test_criterion_1 holds the 2 s strictly)
    failed = [line for line in done.stdout.splitlines() if line.endswith("FAIL")]
    if done.returncode == 1 and len(failed) == 1 and failed[0].startswith("1. the turtle reaches"):
        assert "s too long" in done.stdout and "farthest 0.0" in done.stdout, done.stdout
        return
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.splitlines()[-1] == "10 of 10 hold", done.stdout
    assert all(case.find("failure") is None for case in cases)


def test_a_slowed_status_monitor_fails_the_period_with_its_reason(tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text(PERIOD_ONLY)
    with running_system() as system:
        assert system.run_cli("param", "set", "status_monitor", "rate", "5").returncode == 0
        done = system.run_cli("verify", str(spec), timeout=120)
        assert done.returncode == 1, done.stdout + done.stderr
        assert "FAIL" in done.stdout and "why: 0% of periods within the tolerance, 95% required" in done.stdout
        data = json.loads(system.run_cli("verify", str(spec), "--json", timeout=120).stdout)
        measured = data["verdicts"][0]["measured"]
        mean = re.search(r"mean ([\d.]+) ms", measured)  # 5 Hz: 200 ms, to the scheduling of a loaded machine
        assert data["ok"] is False and mean and abs(float(mean[1]) - 200.0) < 2.0, measured  # CI: "mean 199.9"


def test_no_system_is_exit_3(tmp_path):
    import subprocess

    spec = tmp_path / "spec.toml"
    spec.write_text(PERIOD_ONLY)
    done = subprocess.run(
        [*turtlectl(), "verify", str(spec), "--connect", f"tcp/127.0.0.1:{free_port()}"], capture_output=True, text=True
    )
    assert done.returncode == 3 and "no turtlectl system" in done.stderr, done.stderr


def test_a_router_without_nodes_is_exit_3_not_a_vacuous_pass(tmp_path):
    """Against a bare `turtlectl router` verify says there is no system at once, rather than run
    27 s and pass no_errors and round_trip on no nodes and no topics."""
    import subprocess

    from tests.integration.harness import Router

    spec = tmp_path / "spec.toml"
    spec.write_text('intent = "x"\n[[criterion]]\ncheck = "no_errors"\nminutes = 1\n')
    router = Router()
    router.start()
    try:
        done = subprocess.run(
            [*turtlectl(), "verify", str(spec), "--short", "1", "--connect", router.endpoint],
            capture_output=True,
            text=True,
            timeout=60,
        )
    finally:
        router.kill()
    assert done.returncode == 3, done.stdout + done.stderr
    assert "no nodes are running at" in done.stderr and "nothing to verify" in done.stderr


#: a user's own navigator in place of ours: takes 3 s a goal, reports 0.5 s, logs an error a second
SLOW_NAVIGATOR = """
import time

import msgspec

from turtlectl import Interface
from turtlectl.messages import NavigateToRequest, NavigateToResponse


class SlowNavigator:
    Params = msgspec.defstruct("SlowParams", [("delay", float, 3.0)], forbid_unknown_fields=True)
    Interface = Interface(serves=("navigate_to",))

    def __init__(self, node):
        self.node = node
        self.pending = []
        node.serve("navigate_to", NavigateToRequest, NavigateToResponse, self.goal)
        node.timer(0.05, self.tick)
        node.timer(1.0, lambda: node.log.error("wheel encoder lost"))

    def goal(self, request):
        self.pending.append((time.monotonic() + self.node.params.delay, request))

    def tick(self):
        for due, request in list(self.pending):
            if time.monotonic() >= due:
                self.pending.remove((due, request))
                goal = request.body
                request.respond(NavigateToResponse(success=True, time_taken=0.5, x=goal.x, y=goal.y, theta=goal.theta))
"""

USER_SYSTEM = """
[[node]]
name = "sim"
run = "sim"

[[node]]
name = "status_monitor"
run = "status_monitor"

[[node]]
name = "navigator"
run = "./slow_navigator.py:SlowNavigator"
"""

EVERY_KIND = textwrap.dedent(
    """
    intent = "the capstone's criteria, one of each kind"

    [[criterion]]
    check = "goal"
    goals = [[6.5, 5.5, 90.0]]
    within_s = 2.0
    distance_m = 0.2

    [[criterion]]
    check = "reported_time"
    goals = [[6.0, 5.0, 0.0]]
    within_s = 0.1

    [[criterion]]
    check = "no_errors"
    node = "navigator"
    minutes = 5

    [[criterion]]
    check = "messages"
    key = "nobody/publishes"
    count = 3
    within_s = 2

    [[criterion]]
    check = "round_trip"
    keys = ["robot/status", "junk/state"]
    within_s = 2

    [[criterion]]
    check = "period"
    key = "robot/status"
    period_ms = 100
    tolerance_ms = 10
    samples = 50
    """
)  # 50 periods, as the capstone's criterion 2: over 20, one late tick on a loaded CI machine (two periods
# of 116 and 84 ms) made 90 % within, below the 95 % share, and the control of this test failed


def test_each_kind_of_criterion_fails_with_its_reason_on_a_system_made_to_miss_it(tmp_path):
    """A user's navigator that takes 3 s fails "goal within 2 s" with the time measured; its
    reported 0.5 s fails reported_time; its error a second fails no_errors (shortened, and said
    so); a key nobody publishes fails messages; a payload that is not its type fails round_trip;
    the status monitor's period still holds.  The JUnit report has one failure per miss."""
    (tmp_path / "slow_navigator.py").write_text(SLOW_NAVIGATOR)
    (tmp_path / "launch.toml").write_text(USER_SYSTEM)
    spec = tmp_path / "spec.toml"
    spec.write_text(EVERY_KIND)
    junit = tmp_path / "out.xml"
    with running_system(tmp_path / "launch.toml", ready=("sim", "status_monitor", "navigator"), cwd=tmp_path) as system:
        stop = threading.Event()

        def junk() -> None:  # a TurtleStatus that is not one, 10 times a second
            while not stop.wait(0.1):
                system.session.put("junk/state", b"not msgpack", encoding="application/msgpack;turtlectl/TurtleStatus")

        feeder = threading.Thread(target=junk, daemon=True)
        feeder.start()
        try:
            done = system.run_cli("verify", str(spec), "--short", "3", "--junit", str(junit), timeout=180)
        finally:
            stop.set()
            feeder.join()
        info = system.run_cli("node", "info", "navigator").stdout  # what no_errors reads
        assert "ERRORS " in info and "logged, the last: wheel encoder lost" in info, info
    out = done.stdout
    assert done.returncode == 1, out + done.stderr
    rows = {line.split("  ")[0]: line for line in out.splitlines()}
    assert rows["1 goal within 2 s and 0.2 m"].endswith("FAIL") and "(6.5, 5.5) took 3.0" in out, out
    assert "s too long" in out
    assert "(6, 5) reported 0.500 s, the client measured 3.0" in out
    assert "shortened to 3 s (--short)" in out and "navigator logged " in out and "wheel encoder lost" in out
    assert "only 0 of 3 messages within 2 s" in out
    assert "junk/state: none decoded; " in out and "skipped, the last: " in out
    assert rows["robot/status every 100 ± 10 ms"].endswith("ok"), out
    assert out.splitlines()[-1] == "1 of 6 hold; 5 fail", out
    suite = ET.parse(junit).getroot().find("testsuite")
    assert suite is not None and suite.get("failures") == "5" and suite.get("tests") == "6"


SIMULATED = """intent = "a goal and half a minute without errors, in simulated time"
[[criterion]]
check = "goal"
name = "goal"
goals = [[8.5, 5.5, 180.0]]
within_s = 2.5
distance_m = 0.01
[[criterion]]
check = "no_errors"
name = "quiet"
minutes = 0.5
[[criterion]]
check = "reported_time"
name = "reported"
goals = [[5.5, 5.5, 0.0]]
within_s = 0.1
"""


def test_verify_at_5x_measures_in_simulated_time_and_finishes_sooner(tmp_path):
    """`verify --launch FILE --time-scale 5` runs the system five times as fast and
    measures in its simulated time: half a minute without errors is 30 simulated seconds, a
    goal's time and its time_taken are in simulated seconds (they agree), all sooner."""
    import subprocess
    import time

    spec = tmp_path / "spec.toml"
    spec.write_text(SIMULATED)
    started = time.monotonic()
    done = subprocess.run(
        [*turtlectl(), "verify", str(spec), "--launch", str(ROOT / "launch.toml"), "--time-scale", "5", "--json"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    wall = time.monotonic() - started
    assert done.returncode == 0, done.stdout + done.stderr
    rows = {row["what"]: row for row in json.loads(done.stdout)["verdicts"]}
    assert rows["quiet"]["measured"].startswith("30 s,"), rows["quiet"]
    assert rows["reported"]["ok"], rows["reported"]
    assert wall < 30.0, f"30 simulated seconds took {wall:.0f} s of wall clock"
    time_scale_alone = subprocess.run(
        [*turtlectl(), "verify", str(spec), "--time-scale", "5", "--connect", f"tcp/127.0.0.1:{free_port()}"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert time_scale_alone.returncode == 2 and "--launch" in time_scale_alone.stderr


PARAMETERS = """intent = "each node with the parameters it was meant to have"
[[criterion]]
check = "parameters"
[criterion.params]
navigator = { delay = 3.0 }
status_monitor = { rate = 10.0 }
"""


def test_parameters_hold_for_a_users_nodes_and_a_difference_names_node_parameter_and_values(tmp_path):
    """A student's system (their own navigator kind with its own parameter): the parameters
    criterion holds against the launch file it was started from and the spec's values; a launch
    file that gives the navigator another delay fails, one line naming node, parameter, expected
    and running; a parameter changed while it runs fails against the spec; no launch file and
    no values is a failure saying what to give."""
    (tmp_path / "slow_navigator.py").write_text(SLOW_NAVIGATOR)
    (tmp_path / "launch.toml").write_text(USER_SYSTEM)
    (tmp_path / "other.toml").write_text(
        USER_SYSTEM.replace(
            'run = "./slow_navigator.py:SlowNavigator"',
            'run = "./slow_navigator.py:SlowNavigator"\nparams = { delay = 2.0 }',
        )
    )
    spec = tmp_path / "spec.toml"
    spec.write_text(PARAMETERS)
    bare = tmp_path / "bare.toml"
    bare.write_text('intent = "i"\n[[criterion]]\ncheck = "parameters"\n')
    with running_system(tmp_path / "launch.toml", ready=("sim", "status_monitor", "navigator"), cwd=tmp_path) as system:
        held = system.run_cli("verify", str(spec), "--launch-file", str(tmp_path / "launch.toml"), timeout=60)
        assert held.returncode == 0, held.stdout + held.stderr
        assert "3 nodes' parameters read, 0 differ" in held.stdout, held.stdout
        differs = system.run_cli("verify", str(spec), "--launch-file", str(tmp_path / "other.toml"), timeout=60)
        assert differs.returncode == 1, differs.stdout + differs.stderr
        assert "why: navigator.delay: the launch file 2.0, running 3.0" in differs.stdout, differs.stdout
        assert system.run_cli("param", "set", "status_monitor", "rate", "5").returncode == 0
        changed = system.run_cli("verify", str(spec), timeout=60)
        assert changed.returncode == 1 and "status_monitor.rate: the spec 10.0, running 5.0" in changed.stdout
        nothing = system.run_cli("verify", str(bare), timeout=60)
        assert nothing.returncode == 1 and "no launch file to compare with" in nothing.stdout, nothing.stdout


DRIVING = """intent = "no errors while goals are driven"
[[criterion]]
check = "no_errors"
name = "quiet while driving"
minutes = 1
goals = [[3.0, 3.0, 0.0], [8.0, 8.0, 90.0]]
"""


def test_no_errors_drives_the_listed_goals_meanwhile_and_says_how_they_ended(tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text(DRIVING)
    with running_system() as system:
        done = system.run_cli("verify", str(spec), "--short", "6", "--json", timeout=90)
    assert done.returncode == 0, done.stdout + done.stderr
    (verdict,) = json.loads(done.stdout)["verdicts"]
    assert verdict["ok"] and "while goals are driven; shortened to 6 s" in verdict["required"], verdict
    driven = re.search(r"(\d+) goals? driven: (\d+) reached", verdict["measured"])
    assert driven and int(driven[2]) >= 1, verdict  # a 5 m goal takes about 2 s: one reached at least
