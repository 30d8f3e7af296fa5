"""cli.verify.spec and report (issue 26, a first part): a specification file parsed strictly,
each mistake one line naming the file and key path (exit 2); the table of verdicts."""

from __future__ import annotations

from pathlib import Path

import pytest

from turtlectl.cli.errors import ExitCode, exit_code
from turtlectl.cli.verify.report import Verdict, table
from turtlectl.cli.verify.spec import Goals, Period, SpecError, load_spec, parse_spec

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
    from turtlectl.cli.verify.checks import _periods

    stamps = [i * 0.100 for i in range(5)]
    arrivals = [0.001, 0.101, 0.235, 0.301, 0.401]  # the third delivered 34 ms late
    times = list(zip(arrivals, stamps, strict=True))
    published, how = _periods(times, "publisher")
    assert published == pytest.approx([100.0] * 4) and how == "published"
    arrived, how = _periods(times, "subscriber")
    assert arrived == pytest.approx([100.0, 134.0, 66.0, 100.0]) and how == "arrived"
    unstamped, how = _periods([(t, None) for t in arrivals], "publisher")
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
