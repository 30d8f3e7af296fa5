"""cli.verify.document (`turtlectl spec`): a specification as the capstone's Markdown
template; a specification written as TOML that parses back to itself; the skeleton made from
a live graph and its measured periods."""

from __future__ import annotations

from pathlib import Path

import pytest

from turtlectl.cli.verify.document import (
    INTENT_PLACEHOLDER,
    markdown,
    rounded_period,
    skeleton,
    to_toml,
)
from turtlectl.cli.verify.spec import Period, Spec, load_spec, parse_spec
from turtlectl.runtime.client.graph import Graph, NodeRow, ServiceRow, TopicRow

ROOT = Path(__file__).resolve().parents[3]
CAPSTONE = ROOT / "docs" / "capstone.toml"


def test_the_capstone_as_markdown_has_its_template_and_numbers():
    spec = load_spec(CAPSTONE)
    text = markdown(spec)
    sections = ["## Intent", "## System Architecture", "## Interfaces", "## Success Criteria", "## Non-Goals"]
    assert [text.index(s) for s in sections] == sorted(text.index(s) for s in sections)
    assert "navigates a turtlesim turtle to goal positions" in text
    for node in ("navigator", "status_monitor", "obstacle_detector"):
        assert f"### {node}\nInput: " in text
    assert "### navigator\nInput: `navigate_to`, `turtle1/pose`, `obstacles`\nOutput: `turtle1/cmd_vel`\n" in text
    assert (
        "### Topic: robot/status\nMessage Type: turtlectl/TurtleStatus\nFrequency: 10 Hz, every 100 ms (± 10 ms)\n"
        in text
    )
    assert "Publishers: obstacle_detector\nSubscribers: navigator\n" in text  # the nodes that declare it an input
    assert "### Service: navigate_to\nRequest: NavigateToRequest\n" in text
    checks = [line for line in text.splitlines() if line.startswith("- [ ] ")]
    assert len(checks) == len(spec.criterion) == 7
    assert [c.split(" ", 4)[3] for c in checks] == ["1.", "2.", "3.", "4.", "5.", "6.", "7."]
    assert "within 2 s" in checks[0] and "0.2 m" in checks[0]
    assert "100 ± 10 ms" in checks[1]
    assert "10 messages on obstacles" in checks[2]
    assert "launch file's parameters" in checks[3]
    assert "navigator runs 5 min without errors while driving goals" in checks[4]
    assert "0.1 s" in checks[5]
    assert "round-trip" in checks[6]
    assert "\n".join(f"- {g}" for g in spec.non_goals) in text


def test_an_unnamed_criterion_is_its_label_alone():
    spec = parse_spec(
        'intent = "i"\n[[criterion]]\ncheck = "period"\nkey = "a"\nperiod_ms = 50\ntolerance_ms = 5\n', "f"
    )
    assert "- [ ] a every 50 ± 5 ms\n" in markdown(spec)


def test_an_empty_spec_says_what_it_lacks():
    text = markdown(parse_spec('intent = "i"\n', "f"))
    assert "No nodes declared." in text and "No criteria declared." in text and "None declared." in text


def test_the_capstone_written_as_toml_parses_back_to_itself():
    spec = load_spec(CAPSTONE)
    assert parse_spec(to_toml(spec), "again") == spec


def test_strings_are_escaped_for_toml():
    spec = Spec(intent='a "quoted"\\ line\nand\ta\x7fbell\x07 and ünïcode 🐢', non_goals=["x = [1]"])
    assert parse_spec(to_toml(spec), "f") == spec
    assert "non_goals = [" in to_toml(spec)


@pytest.mark.parametrize(
    ("mean", "period"), [(99.7, 100.0), (100.4, 100.0), (200.3, 200.0), (16.02, 16.0), (33.4, 33.3), (1000.2, 1000.0)]
)
def test_a_measured_period_is_rounded_as_a_spec_states_it(mean, period):
    assert rounded_period(mean) == period


def _graph() -> Graph:
    return Graph(
        nodes=[NodeRow("sim", 1, "h", 1.0), NodeRow("monitor", 2, "h", 1.0)],
        topics=[
            TopicRow("pose", "Pose", ["sim"], ["monitor"]),
            TopicRow("status", "TurtleStatus", ["monitor"], []),
            TopicRow("events", "ParameterEvent", ["sim", "monitor"], []),
            TopicRow("cmd", "Twist", [], ["sim"]),  # nobody publishes it: not a topic of the spec
            TopicRow("turtlectl/parameter_events", "ParameterEvent", ["sim", "monitor"], []),  # the runtime's own
        ],
        services=[ServiceRow("reset", "Reset", ["sim", "monitor"]), ServiceRow("teleport", "Teleport", ["sim"])],
    )


def test_a_skeleton_from_the_graph_and_its_periods():
    spec = skeleton(_graph(), {"status": (100.0, 10.0), "pose": (16.0, 1.6)})
    assert spec.intent == INTENT_PLACEHOLDER and spec.non_goals == []
    nodes = {n.name: n for n in spec.node}
    assert nodes["sim"].inputs == ["cmd", "reset", "teleport"] and nodes["sim"].outputs == ["events", "pose"]
    assert nodes["monitor"].inputs == ["pose", "reset"] and nodes["monitor"].outputs == ["events", "status"]
    topics = {t.key: t for t in spec.topic}
    assert set(topics) == {"pose", "status", "events"}
    assert (topics["status"].publisher, topics["status"].period_ms, topics["status"].tolerance_ms) == (
        "monitor",
        100.0,
        10.0,
    )
    assert topics["events"].publisher == "" and topics["events"].period_ms is None  # two publishers, not measured
    assert {(s.key, s.request, s.server) for s in spec.service} == {
        ("reset", "Reset", ""),
        ("teleport", "Teleport", "sim"),
    }
    assert spec.criterion == [
        Period(key="pose", period_ms=16.0, tolerance_ms=1.6),
        Period(key="status", period_ms=100.0, tolerance_ms=10.0),
    ]
    text = to_toml(spec)
    assert parse_spec(text, "skeleton") == spec
    assert 'intent = "TODO: what the system is for"\nnon_goals = []\n' in text
    assert '[[criterion]]\ncheck = "period"\nkey = "pose"\nperiod_ms = 16.0\ntolerance_ms = 1.6\n' in text


def test_a_measured_period_gets_a_tolerance_of_10_percent_at_least_5_ms():
    from turtlectl.cli.verify.skeleton import period_of

    assert period_of([(i * 0.1, i * 0.1) for i in range(10)]) == (100.0, 10.0)
    assert period_of([(i * 0.016, i * 0.016) for i in range(10)]) == (16.0, 5.0)
    assert period_of([(0.0, 0.0), (0.1, 0.1)]) is None  # too few to say


def test_a_stall_in_the_measuring_window_does_not_make_the_skeletons_period():
    """The typical gap is the period: with the mean, a 64 ms topic whose publisher stalled once in
    the 2 s window gave `turtles every 71 ± 7.1 ms`, and the skeleton failed its own system
    (74 % within)."""
    from turtlectl.cli.verify.skeleton import period_of

    stamps = [i * 0.064 for i in range(25)] + [25 * 0.064 + 0.25 + i * 0.064 for i in range(6)]
    assert period_of([(s, s) for s in stamps]) == (64.0, 6.4)


def test_spec_show_gives_no_verdict_nobody_has_measured():
    # a specification printed is not a system checked: no ✅ (held) or ❌ (failed) before a line
    text = markdown(load_spec(CAPSTONE))
    assert not [line for line in text.splitlines() if line.startswith(("✅", "❌"))]
    criteria = text.split("## Success Criteria\n\n", 1)[1].split("\n\n", 1)[0].splitlines()
    assert criteria and all(line.startswith("- [ ] ") for line in criteria)
    non_goals = text.split("## Non-Goals\n\n", 1)[1].strip().splitlines()
    assert non_goals == [f"- {g}" for g in load_spec(CAPSTONE).non_goals]
