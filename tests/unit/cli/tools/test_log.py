"""cli.tools.log: what ``turtlectl log`` takes (levels, durations, node globs), which records it
keeps, and how it writes them (a line for people, coloured by level on a terminal; JSON)."""

from __future__ import annotations

import json
import time

import pytest

from turtlectl.cli.tools.log import (
    LogFilter,
    clock_time,
    json_of,
    level_name,
    level_number,
    node_matches,
    since_seconds,
    text_of,
    unmatched,
    use_colour,
)
from turtlectl.messages import Log
from turtlectl.runtime.client.errors import BadInput

STAMP = 1_764_100_000_250_000_000  # ns: .250 s past a whole second
CLOCK = time.strftime("%H:%M:%S", time.localtime(STAMP // 1_000_000_000)) + ".250"


def record(level: int = 20, node: str = "navigator", message: str = "goal reached", stamp: int = STAMP) -> Log:
    return Log(level=level, node=node, message=message, file="/x/nodes/navigator.py", function="f", line=7, stamp=stamp)


@pytest.mark.parametrize(
    ("typed", "number"),
    [("debug", 10), ("INFO", 20), ("Warning", 30), ("warn", 30), ("error", 40), ("critical", 50), ("FATAL", 50)],
)
def test_levels_are_named_as_python_and_ros_name_them(typed, number):
    assert level_number(typed) == number


def test_an_unknown_level_is_bad_input_naming_the_known_ones():
    with pytest.raises(BadInput, match="unknown log level 'loud' \\(known: DEBUG, INFO, WARNING, ERROR, CRITICAL"):
        level_number("loud")


def test_a_level_between_the_named_ones_is_shown_as_python_shows_it():
    assert [level_name(n) for n in (10, 30, 50, 25)] == ["DEBUG", "WARNING", "CRITICAL", "Level 25"]


@pytest.mark.parametrize(
    ("typed", "seconds"),
    [("30s", 30.0), ("5m", 300.0), ("1h30m", 5400.0), ("250ms", 0.25), ("2", 2.0), ("1.5m", 90.0), ("1d", 86400.0)],
)
def test_since_takes_a_duration_with_its_unit(typed, seconds):
    assert since_seconds(typed) == pytest.approx(seconds)


@pytest.mark.parametrize("typed", ["", "soon", "5x", "0s", "-5s", "5 minutes"])
def test_since_refuses_what_is_not_a_duration(typed):
    with pytest.raises(BadInput, match="--since"):
        since_seconds(typed)


def test_a_node_is_named_whole_or_by_a_glob():
    assert node_matches("navigator", ())  # no --node: every node
    assert node_matches("navigator", ("navigator",)) and not node_matches("turtle2/navigator", ("navigator",))
    assert node_matches("turtle2/navigator", ("turtle2/*",)) and not node_matches("navigator", ("turtle2/*",))
    assert node_matches("status_monitor", ("sim", "status*"))
    assert not node_matches("Navigator", ("navigator",))  # names are case-sensitive, as keys are
    # a namespace names its nodes (as launch --only), and ROS's leading slash is dropped
    assert node_matches("turtle2/navigator", ("turtle2",)) and not node_matches("turtle22/navigator", ("turtle2",))
    assert node_matches("navigator", ("/navigator",)) and node_matches("turtle2/navigator", ("/turtle2",))


def test_the_filter_keeps_records_at_the_level_of_the_nodes_since_the_time():
    records = [
        record(10, "sim", stamp=100),
        record(20, "navigator", stamp=200),
        record(30, "navigator", stamp=300),
        record(40, "turtle2/navigator", stamp=400),
    ]

    def kept(wanted: LogFilter) -> list[int]:
        return [r.stamp for r in records if wanted.wants(r)]

    assert kept(LogFilter()) == [100, 200, 300, 400]
    assert kept(LogFilter(level=30)) == [300, 400]
    assert kept(LogFilter(nodes=("navigator",))) == [200, 300]
    assert kept(LogFilter(nodes=("*navigator",), level=40)) == [400]
    assert kept(LogFilter(since_ns=250)) == [300, 400]


def test_a_record_for_people_is_its_time_level_node_and_text():
    assert clock_time(STAMP) == CLOCK
    assert text_of(record()) == f"{CLOCK} INFO     navigator: goal reached"
    assert text_of(record(30, "turtle2/navigator", "no recent scan")) == (
        f"{CLOCK} WARNING  turtle2/navigator: no recent scan"
    )


def test_a_traceback_is_indented_under_its_record():
    text = text_of(record(40, message="failed\nTraceback (most recent call last):\n  File x\n\nValueError: bad\n"))
    assert text.splitlines() == [
        f"{CLOCK} ERROR    navigator: failed",
        "    Traceback (most recent call last):",
        "      File x",
        "",
        "    ValueError: bad",
    ]


def test_colours_by_level_only_when_asked():
    assert "\033[" not in text_of(record(40), colour=False)
    info = text_of(record(20), colour=True)
    assert info == f"{CLOCK} \033[32mINFO    \033[0m navigator: goal reached"  # INFO: only its name, green
    assert text_of(record(30), colour=True).startswith("\033[33m")  # WARNING: the line yellow
    assert text_of(record(40), colour=True).startswith("\033[31m") and text_of(record(40), colour=True).endswith(
        "\033[0m"
    )
    assert text_of(record(50), colour=True).startswith("\033[1;31m")  # CRITICAL: bold red
    assert text_of(record(10), colour=True).startswith("\033[2m")  # DEBUG: dim
    traceback = text_of(record(40, message="failed\nValueError: bad"), colour=True).splitlines()
    assert all(line.startswith("\033[31m") and line.endswith("\033[0m") for line in traceback)  # each line coloured


def test_colour_on_a_terminal_unless_no_color_or_a_dumb_terminal():
    assert use_colour(True, {}) and use_colour(True, {"TERM": "xterm", "NO_COLOR": ""})
    assert not use_colour(False, {})  # piped
    assert not use_colour(True, {"NO_COLOR": "1"})
    assert not use_colour(True, {"TERM": "dumb"})


def test_json_is_the_message_as_echo_writes_it():
    written = json.loads(json_of(record(30)))
    assert written == {
        "type": "turtlectl/Log",
        "level": 30,
        "node": "navigator",
        "message": "goal reached",
        "file": "/x/nodes/navigator.py",
        "function": "f",
        "line": 7,
        "stamp": STAMP,
        "seq": 0,
    }


def test_a_node_filter_that_matches_no_running_node_suggests_the_nearest():
    running = ["navigator", "sim", "turtle2/navigator"]
    assert unmatched(("navigatr",), running) == (
        "no running node matches --node navigatr; did you mean navigator? (running: navigator, sim, turtle2/navigator)"
    )
    assert unmatched(("turtle3/*",), running) == (
        "no running node matches --node turtle3/* (running: navigator, sim, turtle2/navigator)"
    )
    assert unmatched(("navigatr", "turtle2/navigatr"), running).startswith(
        "no running node matches --node navigatr, turtle2/navigatr; did you mean navigator, turtle2/navigator?"
    )
