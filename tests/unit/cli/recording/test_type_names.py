"""Recordings and type names: a user's TurtleStatus and turtlectl's in one recording, each read back as
its own type; a recording made before types were named by package (built-ins tagged bare, ``Pose``)
still read, its built-ins as ``turtlectl/<Name>``."""

from __future__ import annotations

import json

from turtlectl.cli.recording.bag import BagWriter
from turtlectl.cli.recording.reading import Recording
from turtlectl.messages import Message, Pose, TurtleStatus, encode, encoding_for, to_json
from turtlectl.messages.codec import register, type_name
from turtlectl.messages.jsonform import json_schema

T0 = 1_700_000_000_000_000_000


# its own package: a type registered here stays for the whole test process, where test_naming declares capstone_msgs/TurtleStatus
class Status(Message, tag="student_msgs/TurtleStatus"):
    """A student's own status."""

    x: float  # m: position
    mood: str = "fine"  # -: how it goes


THEIRS = TurtleStatus(x=1, y=2, theta=3, vel_x=0, vel_y=0, battery=50)


def test_a_users_turtle_status_and_turtlectls_in_one_recording(tmp_path):
    register(Status)  # as the recorder knows it: learnt from the node that uses it
    path = tmp_path / "run.mcap"
    writer = BagWriter(path)
    writer.add("robot/status", encoding_for(TurtleStatus), encode(THEIRS), T0)
    writer.add("capstone/status", encoding_for(Status), encode(Status(x=4.0)), T0 + 1)
    writer.close()
    recording = Recording(path)
    types = {t.key: t.type_name for t in recording.info().topics}
    assert types == {"robot/status": "turtlectl/TurtleStatus", "capstone/status": "student_msgs/TurtleStatus"}
    messages = {r.key: r.message() for r in recording.records()}
    assert messages["robot/status"] == THEIRS
    assert type_name(type(messages["capstone/status"])) == "student_msgs/TurtleStatus"
    assert messages["capstone/status"].mood == "fine" and messages["capstone/status"].x == 4.0


def _legacy(schema: dict, bare: str) -> dict:
    """A schema as a recording made before wrote it: titled and tagged with the bare name."""
    text = json.dumps(schema).replace(type_name(Pose), bare)
    return json.loads(text)


def test_a_recording_made_before_types_were_named_by_package_is_still_read(tmp_path):
    from mcap.writer import Writer

    path = tmp_path / "old.mcap"
    pose = Pose(x=1.0, y=2.0, theta=0.5, stamp=T0)
    with open(path, "wb") as f:
        writer = Writer(f)
        writer.start(profile="turtlectl", library="turtlectl")
        schema = writer.register_schema("Pose", "jsonschema", json.dumps(_legacy(json_schema(Pose), "Pose")).encode())
        channel = writer.register_channel(
            "turtle1/pose", "json", schema, metadata={"zenoh_encoding": "application/msgpack;Pose"}
        )
        data = to_json(pose).replace(b'"turtlectl/Pose"', b'"Pose"')
        assert b'"type":"Pose"' in data
        writer.add_message(channel, log_time=T0, publish_time=T0, data=data, sequence=0)
        writer.finish()
    recording = Recording(path)
    (topic,) = recording.info().topics
    assert topic.type_name == "turtlectl/Pose"
    (record,) = list(recording.records())
    assert record.type_name == "turtlectl/Pose" and record.encoding == "application/msgpack;turtlectl/Pose"
    assert record.message() == pose
