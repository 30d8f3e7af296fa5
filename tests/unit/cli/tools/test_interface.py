"""`turtlectl interface list / show`: every type of the wire contract, each with
every field its Struct has, the units from the one reference (messages.reference)."""

from __future__ import annotations

import json
import signal
import subprocess
import sys

import msgspec
import pytest

from tests.unit.cli.test_main import invoke
from turtlectl.messages import ALL_TYPES, Twist
from turtlectl.runtime.client.errors import ExitCode


@pytest.fixture(autouse=True)
def sigint_back():
    """A command ignores Ctrl-C once its result is out (the process ends there); in this
    process the handler comes back after each test."""
    previous = signal.getsignal(signal.SIGINT)
    yield
    signal.signal(signal.SIGINT, previous)


def turtlectl(*argv: str) -> subprocess.CompletedProcess:
    """The real command, as a user runs it."""
    return subprocess.run(
        [sys.executable, "-m", "turtlectl.cli", *argv], capture_output=True, text=True, timeout=60, check=False
    )


def test_list_names_every_type_with_the_keys_that_carry_it():
    code, text = invoke("interface", "list")
    assert code == 0
    for t in ALL_TYPES:
        assert any(line.startswith(f"turtlectl/{t.__name__} ") for line in text.splitlines()), t.__name__
    code, out = invoke("interface", "list", "--json")
    rows = {r["type"]: r for r in json.loads(out)}
    assert rows["turtlectl/Twist"]["keys"] == ["turtle1/cmd_vel", "<turtle>/cmd_vel"] and rows[
        "turtlectl/TurtleStatus"
    ]["keys"] == ["robot/status"]
    assert set(rows) == {f"turtlectl/{t.__name__}" for t in ALL_TYPES}


@pytest.mark.parametrize("msg_type", ALL_TYPES, ids=lambda t: t.__name__)
def test_show_gives_every_field_with_its_unit_and_default(msg_type):
    code, out = invoke("interface", "show", msg_type.__name__, "--json")
    assert code == 0
    shown = json.loads(out)
    names = [f.name for f in msgspec.inspect.type_info(msg_type).fields]
    assert [f["name"] for f in shown["fields"]] == names
    assert all(f["unit"] and f["meaning"] for f in shown["fields"])
    assert shown["encoding"] == f"application/msgpack;turtlectl/{msg_type.__name__}"
    assert shown["type"] == f"turtlectl/{msg_type.__name__}" and shown["doc"]


def test_show_is_readable_and_case_does_not_matter():
    code, text = invoke("interface", "show", "twist")
    assert code == 0
    assert text.startswith('turtlectl/Twist: msgpack map tagged "type": "turtlectl/Twist"')
    assert "linear   float  0        m/s" in text and "keys: turtle1/cmd_vel" in text
    assert Twist.__name__ in text


def test_an_unknown_type_is_one_line_naming_the_known_ones_exit_2():
    done = turtlectl("interface", "show", "Odometry")
    assert done.returncode == ExitCode.BAD_INPUT, done
    assert done.stderr.strip().startswith("turtlectl: error: unknown message type 'Odometry' (known: turtlectl/Ack,"), (
        done.stderr
    )
    assert "Traceback" not in done.stderr and done.stdout == ""


def test_list_gives_each_type_its_whole_first_sentence():
    """`interface list` does not cut ParameterEvent's summary mid-sentence (its first line)."""
    from turtlectl.cli.tools.interface import listing
    from turtlectl.messages.fieldtext import doc

    for row, t in zip(listing(), ALL_TYPES, strict=True):
        first = " ".join(doc(t).split("\n\n", 1)[0].split())
        assert row["summary"] == first and row["summary"].endswith("."), (t.__name__, row["summary"])
    code, text = invoke("interface", "list")
    assert "ParameterEvent" in text and "changes at run time (``turtlectl param set``)" in text
