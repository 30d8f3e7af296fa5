"""Types named by package (messages.naming): a user's ``TurtleStatus`` and turtlectl's coexist in one
process, each under its full name ``package/Name``; a short name is taken where it is unambiguous."""

from __future__ import annotations

import importlib
import sys
import textwrap

import msgspec
import pytest

from turtlectl.messages import Message, TurtleStatus, decode_any, encode, encoding_for, type_from_encoding
from turtlectl.messages.codec import named, register, type_name, type_short_name
from turtlectl.messages.keys import EntityInfo, entity_token, parse_entity_token, type_from_chunk, type_key
from turtlectl.messages.naming import AmbiguousType, TypeNameError, full_name, lookup, names, package_of

CAPSTONE = '''
from turtlectl import Message


class TurtleStatus(Message, tag="TurtleStatus"):
    """The lesson's own status."""

    x: float  # m: position
    mood: str = "fine"
'''


@pytest.fixture
def capstone_msgs(tmp_path, monkeypatch):
    """A student's module ``capstone_msgs.py`` declaring its own TurtleStatus, imported as a user would."""
    (tmp_path / "capstone_msgs.py").write_text(textwrap.dedent(CAPSTONE))
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("capstone_msgs")
    yield module
    sys.modules.pop("capstone_msgs", None)


def test_a_users_turtle_status_and_the_builtin_coexist_in_one_process(capstone_msgs):
    mine = capstone_msgs.TurtleStatus
    assert type_name(mine) == "capstone_msgs/TurtleStatus" and type_short_name(mine) == "TurtleStatus"
    assert type_name(TurtleStatus) == "turtlectl/TurtleStatus"
    assert register(mine) is mine  # no "two message types named 'TurtleStatus'"
    assert msgspec.msgpack.decode(encode(mine(x=1.0)))["type"] == "capstone_msgs/TurtleStatus"
    assert encoding_for(mine) == "application/msgpack;capstone_msgs/TurtleStatus"
    theirs = TurtleStatus(x=1.0, y=2.0, theta=0.0, vel_x=0.0, vel_y=0.0, battery=100.0)
    assert decode_any(encode(mine(x=1.0))) == mine(x=1.0)
    assert decode_any(encode(theirs)) == theirs
    assert type_from_encoding(encoding_for(mine)) is mine
    assert type_from_encoding(encoding_for(TurtleStatus)) is TurtleStatus
    with pytest.raises(AmbiguousType) as ambiguous:
        named("TurtleStatus")
    # both among the choices (other tests of this process may have registered a TurtleStatus of their own)
    assert {"capstone_msgs/TurtleStatus", "turtlectl/TurtleStatus"} <= set(ambiguous.value.choices)
    assert named("capstone_msgs/TurtleStatus") is mine and named("turtlectl/turtlestatus") is TurtleStatus
    assert named("Pose") is not None  # a short name only one type has


def test_a_tag_with_a_package_is_taken_as_it_is():
    class Status(Message, tag="capstone_interfaces/TurtleStatus"):
        x: float

    assert type_name(Status) == "capstone_interfaces/TurtleStatus"


@pytest.mark.parametrize(
    "tag, module, why",
    [
        ("turtlectl/Pose", "capstone_msgs", "turtlectl's own"),
        ("a/b/C", "capstone_msgs", "package/Name"),
        ("my-type", "capstone_msgs", "package/Name"),
        ("9lives/Cat", "capstone_msgs", "package/Name"),
    ],
)
def test_a_bad_name_fails_when_the_class_is_made(tag, module, why):
    with pytest.raises(TypeNameError, match=why):
        full_name(tag, module)
    with pytest.raises((TypeNameError, TypeError), match=why):
        type(Message)("Bad", (Message,), {"__module__": module}, tag=tag)


def test_the_package_is_where_the_type_is_declared():
    assert package_of("capstone_msgs") == "capstone_msgs"
    assert package_of("capstone_msgs.msg.status") == "capstone_msgs"
    assert package_of("turtlectl.messages.types") == "turtlectl"
    assert full_name("TurtleStatus", "capstone_msgs.msg") == "capstone_msgs/TurtleStatus"


def test_a_script_run_as_main_is_its_own_package(tmp_path):
    import subprocess

    script = tmp_path / "patrol_node.py"
    script.write_text(
        "from turtlectl import Message\nclass Lap(Message, tag='Lap'):\n    n: int = 0\nprint(Lap.__struct_config__.tag)\n"
    )
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "patrol_node/Lap"


def test_a_short_name_is_taken_where_one_type_has_it():
    known = ["turtlectl/Pose", "turtlectl/TurtleStatus", "capstone_msgs/TurtleStatus"]
    assert lookup("pose", known) == "turtlectl/Pose"
    assert lookup("turtlectl/TurtleStatus", known) == "turtlectl/TurtleStatus"
    assert lookup("Nope", known) is None and lookup("other/Pose", known) is None
    with pytest.raises(AmbiguousType) as err:
        lookup("TurtleStatus", known)
    assert err.value.choices == ["capstone_msgs/TurtleStatus", "turtlectl/TurtleStatus"]
    assert str(err.value) == (
        "type 'TurtleStatus' is ambiguous: write one of capstone_msgs/TurtleStatus, turtlectl/TurtleStatus"
    )


def test_a_spec_names_a_type_found_on_a_key_in_full_or_short():
    # verify's interface check: the type found on a key, against the name the spec gives
    assert names("turtlectl/TurtleStatus", "turtlectl/TurtleStatus")
    assert names("TurtleStatus", "capstone_msgs/TurtleStatus") and names("TurtleStatus", "turtlectl/TurtleStatus")
    assert not names("turtlectl/TurtleStatus", "capstone_msgs/TurtleStatus")
    assert not names("Pose", "turtlectl/TurtleStatus") and not names("other/Pose", "turtlectl/Pose")


def test_a_full_name_is_one_key_chunk_with_a_dot_as_a_node_name_is():
    entity = EntityInfo(
        node="turtle2/monitor", pid=7, role="pub", type_name="capstone_msgs/TurtleStatus", key="robot/status"
    )
    token = entity_token(entity)
    assert token == "@turtlectl/entity/turtle2.monitor/7/pub/capstone_msgs.TurtleStatus/robot/status"
    assert parse_entity_token(token) == entity
    assert type_key("capstone_msgs/TurtleStatus", "monitor") == "turtlectl/types/capstone_msgs.TurtleStatus/monitor"
    assert type_from_chunk("turtlectl.Pose") == "turtlectl/Pose"
