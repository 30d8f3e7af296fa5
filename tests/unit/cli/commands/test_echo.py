"""`turtlectl echo` as a user reads it, its stream faked (no router): one field or several,
as text, JSON or CSV, each with the header --csv promises."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from turtlectl.cli.main import app
from turtlectl.cli.tools import topics
from turtlectl.messages import TurtleStatus

STATUSES = [
    TurtleStatus(x=1.5, y=2.0, theta=0.0, vel_x=0.0, vel_y=0.0, battery=90.0, seq=1),
    TurtleStatus(x=1.75, y=2.5, theta=0.0, vel_x=0.0, vel_y=0.0, battery=89.5, seq=2),
]


@pytest.fixture
def two_statuses(monkeypatch):
    def fake_stream(connect, domain, topic, count, timeout, exit_on_loss=False):
        for status in STATUSES[:count]:
            yield topics.Received("robot/status", status)

    monkeypatch.setattr(topics, "stream", fake_stream)


def echo(*argv: str) -> tuple[int, list[str]]:
    result = CliRunner().invoke(app, ["echo", "robot/status", "--count", "2", *argv])
    return result.exit_code, result.stdout.splitlines()


def test_several_fields_are_printed_together(two_statuses):
    assert echo("--field", "x", "--field", "y") == (0, ["1.5 2", "1.75 2.5"])
    code, lines = echo("--field", "x", "--field", "battery", "--json")
    assert code == 0 and [json.loads(line) for line in lines] == [
        {"x": 1.5, "battery": 90.0},
        {"x": 1.75, "battery": 89.5},
    ]
    assert echo("--field", "x", "--field", "y", "--csv") == (0, ["x,y", "1.5,2.0", "1.75,2.5"])


def test_one_field_as_csv_has_its_header_and_as_text_or_json_its_bare_value(two_statuses):
    assert echo("--field", "battery", "--csv") == (0, ["battery", "90.0", "89.5"])
    assert echo("--field", "battery") == (0, ["90", "89.5"])
    assert echo("--field", "battery", "--json") == (0, ["90.0", "89.5"])
