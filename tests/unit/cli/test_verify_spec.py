"""cli.verify.spec and report: a specification file parsed strictly,
each mistake one line naming the file and key path (exit 2); the table of verdicts."""

from __future__ import annotations

from pathlib import Path

import pytest

from turtlectl.cli.verify.report import Verdict, table
from turtlectl.cli.verify.spec import Goals, Period, SpecError, load_spec, parse_spec
from turtlectl.runtime.client.errors import ExitCode, exit_code

ROOT = Path(__file__).resolve().parents[3]


def test_the_capstone_spec_parses_with_its_numbers():
    spec = load_spec(ROOT / "docs" / "capstone.toml")
    goal = next(c for c in spec.criterion if isinstance(c, Goals))
    period = next(c for c in spec.criterion if isinstance(c, Period))
    assert (goal.within_s, goal.distance_m) == (2.0, 0.2)
    assert (period.key, period.period_ms, period.tolerance_ms) == ("robot/status", 100.0, 10.0)
    assert {t.key for t in spec.topic} == {"robot/status", "obstacles"}


@pytest.mark.parametrize(
    ("text", "error"),
    [
        ('intent = "x"\n[[criterion]]\ncheck = "perod"\n', "f.toml: criterion[0].check: Invalid value 'perod'"),
        (
            'intent = "x"\n[[criterion]]\ncheck = "goal"\ngoals = [[1, 2, 3]]\nwithin_s = "2"\ndistance_m = 0.2\n',
            "f.toml: criterion[0].within_s: Expected `float`, got `str`",
        ),
        (
            'intent = "x"\n[[topic]]\nkey = "a"\ntype = "T"\nrate = 3\n',
            "f.toml: topic[0]: Object contains unknown field `rate`",
        ),
        ("[[topic]]\n", "f.toml: topic[0]: Object missing required field `key`"),
        ('intent = "x\n', "f.toml: not valid TOML"),
    ],
)
def test_a_bad_spec_is_one_line_naming_the_key_and_exit_2(text, error):
    with pytest.raises(SpecError) as caught:
        parse_spec(text, "f.toml")
    assert caught.value.message.startswith(error) and exit_code(caught.value) == ExitCode.BAD_INPUT


def test_the_table_gives_each_failure_its_reason_and_counts():
    text = table([Verdict("a", "1", "1", True), Verdict("b", "2 s", "2.66 s", False, "0.66 s too long")])
    assert text.splitlines()[2].endswith("FAIL") and "    why: 0.66 s too long" in text
    assert text.splitlines()[-1] == "1 of 2 hold; 1 fail"


def test_a_period_is_timed_by_the_publishers_stamps_unless_asked_for_arrivals():
    """The CI failure of stop 30: one late delivery on a loaded machine made a 134 ms / 66 ms pair
    at the subscriber while the publisher kept 100 ms.  ``at = "publisher"`` (the default) times
    the messages' own stamps; "subscriber" the arrivals; a type without stamps is timed on arrival
    and says so."""
    from turtlectl.cli.verify.checks import periods_of

    stamps = [i * 0.100 for i in range(5)]
    arrivals = [0.001, 0.101, 0.235, 0.301, 0.401]  # the third delivered 34 ms late
    times = list(zip(arrivals, stamps, strict=True))
    published, how = periods_of(times, "publisher")
    assert published == pytest.approx([100.0] * 4) and how == "published"
    arrived, how = periods_of(times, "subscriber")
    assert arrived == pytest.approx([100.0, 134.0, 66.0, 100.0]) and how == "arrived"
    unstamped, how = periods_of([(t, None) for t in arrivals], "publisher")
    assert unstamped == pytest.approx(arrived) and how == "arrived: its messages have no stamp"
    assert (
        parse_spec(
            'intent = "x"\n[[criterion]]\ncheck = "period"\nkey = "k"\nperiod_ms = 1\ntolerance_ms = 1\n', "f.toml"
        )
        .criterion[0]
        .at
        == "publisher"
    )  # type: ignore[union-attr]
    with pytest.raises(SpecError, match=r"criterion\[0\]\.at: Invalid enum value 'both'"):
        parse_spec(
            'intent = "x"\n[[criterion]]\ncheck = "period"\nkey = "k"\nperiod_ms = 1\ntolerance_ms = 1\nat = "both"\n',
            "f.toml",
        )


def test_seeded_goals_are_the_same_for_the_same_seed_and_in_their_area():
    from turtlectl.cli.verify.goals import goal_list, heading_error

    text = 'intent = "x"\n[[criterion]]\ncheck = "goal"\ngoals = [[1, 2, 3]]\nrandom = 5\nseed = 7\narea = [2, 3, 4, 5]\nwithin_s = 2\ndistance_m = 0.2\nheading_deg = 1\n'
    c = parse_spec(text, "f.toml").criterion[0]
    goals = goal_list(c)  # type: ignore[arg-type]
    assert goals[0] == (1.0, 2.0, 3.0) and len(goals) == 6 and goal_list(c) == goals  # type: ignore[arg-type]
    assert all(2 <= x <= 4 and 3 <= y <= 5 and 0 <= t <= 360 for x, y, t in goals[1:])
    other = parse_spec(text.replace("seed = 7", "seed = 8"), "f.toml").criterion[0]
    assert goal_list(other)[1:] != goals[1:]  # type: ignore[arg-type]
    assert heading_error(359.0, 1.0) == pytest.approx(2.0) and heading_error(90.0, 270.0) == pytest.approx(180.0)


def test_a_long_criterion_runs_its_full_time_unless_shortened_and_says_so():
    from turtlectl.cli.verify.running import _duration
    from turtlectl.cli.verify.spec import NoErrors

    c = NoErrors(node="navigator", minutes=5)
    assert _duration(c, None) == (300.0, "")
    assert _duration(c, 600) == (300.0, "")
    assert _duration(c, 30) == (30.0, "; shortened to 30 s (--short)")


@pytest.mark.parametrize(
    ("text", "error"),
    [
        (
            'intent = "x"\n[[criterion]]\ncheck = "no_error"\n',
            "criterion[0].check: Invalid value 'no_error'; did you mean no_errors?",
        ),
        (
            'intent = "x"\n[[criterion]]\ncheck = "no_errors"\nnode = "a"\nminute = 5\n',
            "criterion[0]: Object contains unknown field `minute`; did you mean minutes?",
        ),
        (
            'intent = "x"\n[[criterion]]\ncheck = "round_trip"\nkey = ["a"]\n',
            "criterion[0]: Object contains unknown field `key`; did you mean keys?",
        ),
        (
            'intent = "x"\n[[topic]]\nkey = "a"\ntype = "T"\nperiod = 3\n',
            "topic[0]: Object contains unknown field `period`; did you mean period_ms?",
        ),
        (
            'intent = "x"\n[[criterion]]\ncheck = "period"\nkey = "k"\nperiod_ms = 1\ntolerance_ms = 1\nsamples = 0\n',
            "criterion[0].samples: Expected `int` >= 1",
        ),
        (
            'intent = "x"\n[[criterion]]\ncheck = "period"\nkey = "k"\nperiod_ms = 1\ntolerance_ms = 1\nshare = 95\n',
            "criterion[0].share: Expected `float` <= 1.0",
        ),
        (
            'intent = "x"\n[[criterion]]\ncheck = "period"\nkey = "k"\nperiod_ms = 1\ntolerance_ms = 1\nat = "subscribr"\n',
            "criterion[0].at: Invalid enum value 'subscribr'; did you mean subscriber?",
        ),
        (
            'intent = "x"\n[[criterion]]\ncheck = "goal"\ngoals = [[1, 2, 3]]\nwithin_s = -2\ndistance_m = 0.2\n',
            "criterion[0].within_s: Expected `float` > 0.0",
        ),
        (
            'intent = "x"\n[[criterion]]\ncheck = "goal"\ngoals = [[nan, 2, 3]]\nwithin_s = 2\ndistance_m = 0.2\n',
            "criterion[0].goals[0][0]: Expected `float` >= -1000000.0",
        ),
        (
            'intent = "x"\n[[criterion]]\ncheck = "goal"\nrandom = 2\narea = [5, 5, 1, 1]\nwithin_s = 2\ndistance_m = 0.2\n',
            "criterion[0].area: not [x_min, y_min, x_max, y_max] with min < max",
        ),
        (
            'intent = "x"\n[[criterion]]\ncheck = "messages"\nname = "a"\nkey = "k"\ncount = 1\n[[criterion]]\ncheck = "messages"\nname = "a"\nkey = "k"\ncount = 1\n',
            "criterion[1].name: 'a' is criterion[0]'s name too",
        ),
        ('intent = "x"\nnon_goal = []\n', "f.toml: Object contains unknown field `non_goal`; did you mean non_goals?"),
        (
            'intent = "x"\n[[criterion]]\ncheck = "goal"\nwithin_s = 2.0\ndistance_m = 0.2\n',
            "criterion[0]: no goals (give goals = [[x, y, theta], ...] or random = N)",
        ),
        (
            'intent = "x"\n[[criterion]]\ncheck = "goal"\ngoals = [[1, 2]]\nwithin_s = 2.0\ndistance_m = 0.2\n',
            "criterion[0].goals[0]: Expected `array` of length 3",
        ),
    ],
)
def test_a_mistake_names_its_key_and_the_nearest_allowed(text, error):
    with pytest.raises(SpecError) as caught:
        parse_spec(text, "f.toml")
    assert error in str(caught.value)
    assert exit_code(caught.value) == ExitCode.BAD_INPUT


def test_the_junit_report_parses_with_one_case_per_verdict_and_the_reasons():
    from xml.etree import ElementTree as ET

    from turtlectl.cli.verify.report import junit

    verdicts = [Verdict("a", "r", "m", True), Verdict("b <&>", "r2", "m2", False, "too slow by 1 s")]
    root = ET.fromstring(junit("spec.toml", verdicts))
    suite = root.find("testsuite")
    assert suite is not None and suite.get("tests") == "2" and suite.get("failures") == "1"
    cases = suite.findall("testcase")
    assert [c.get("name") for c in cases] == ["a", "b <&>"]
    assert cases[0].find("failure") is None and cases[1].find("failure").get("message") == "too slow by 1 s"  # type: ignore[union-attr]
