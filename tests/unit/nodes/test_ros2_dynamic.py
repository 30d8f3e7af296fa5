"""A user's own flat message type across the ROS 2 bridge (nodes.ros2_generic, nodes.ros2_dynamic):
found by its ROS name, validated in the bridge's table, made a Cyclone DDS struct whose CDR is what a
ROS 2 node built with the same ``.msg`` text writes (rosbags' serializer of that text)."""

from __future__ import annotations

import textwrap

import msgspec
import numpy as np
import pytest

from turtlectl import Message
from turtlectl.nodes import ros2_dynamic, ros2_generic, ros2_mapping
from turtlectl.nodes.ros2_table import BridgeTopic


class Reading(Message, tag="gen_msgs/Reading"):
    """A flat type: every kind of field that crosses."""

    value: float
    count: int = 0
    ok: bool = True
    label: str = ""
    samples: list[float] = []
    names: list[str] = []
    corner: tuple[float, float, float] = (0.0, 0.0, 0.0)
    stamp: int = 0
    seq: int = 0


class Corner(msgspec.Struct, frozen=True):
    x: float


class Nested(Message, tag="gen_msgs/Nested"):
    distance: float
    corners: list[Corner] = []


READING = Reading(
    value=1.5, count=-3, label="hé", samples=[1.0, 2.5], names=["a", "b"], corner=(1.0, 2.0, 3.0), stamp=7, seq=2
)


def row(**fields):
    return msgspec.convert(fields, BridgeTopic)


def test_the_struct_is_named_as_ros_names_the_type_and_round_trips():
    sample = ros2_dynamic.to_ros(READING)
    assert type(sample).__idl_typename__ == "gen_msgs::msg::dds_::Reading_"
    back = type(sample).deserialize(sample.serialize())
    assert ros2_dynamic.from_ros(back, Reading) == READING
    assert ros2_dynamic.idl_struct(Reading) is type(sample)  # made once


def test_its_cdr_is_what_a_ros_node_built_with_the_msg_text_writes():
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS2_KILTED)
    store.register(get_types_from_msg(ros2_generic.msg_text(Reading), "gen_msgs/msg/Reading"))
    fields = ros2_generic.fields_of(READING)
    fields.update(samples=np.array(fields["samples"]), corner=np.array(fields["corner"]))
    ros = store.types["gen_msgs/msg/Reading"](**fields)
    data = ros2_dynamic.to_ros(READING).serialize()
    assert bytes(store.serialize_cdr(ros, "gen_msgs/msg/Reading")) == data
    read = store.deserialize_cdr(data, "gen_msgs/msg/Reading")
    assert (read.value, read.count, read.label, list(read.names)) == (1.5, -3, "hé", ["a", "b"])


def test_a_value_the_type_does_not_allow_is_a_value_error():
    struct = ros2_dynamic.idl_struct(Reading)
    with pytest.raises(ValueError):
        ros2_dynamic.from_ros(struct(value=1.0, corner=[1.0, 2.0]), Reading)  # a tuple of 3


def test_a_row_of_a_users_flat_type_crosses_both_ways():
    reading = row(key="reading", ros="/reading", type="gen_msgs/msg/Reading", direction="both")
    assert (reading.message_type, reading.generic, reading.to_ros, reading.from_ros) == (
        "gen_msgs/Reading",
        True,
        True,
        True,
    )
    assert ros2_mapping.to_ros_of("gen_msgs/msg/Reading")[0] is Reading
    assert ros2_mapping.from_ros_of("gen_msgs/msg/Reading")[1] is Reading


def test_a_type_that_is_not_flat_is_one_line_naming_its_field():
    with pytest.raises(msgspec.ValidationError) as err:
        row(key="wall", ros="/wall", type="gen_msgs/msg/Nested")
    text = str(err.value)
    assert "gen_msgs/Nested cannot cross to ROS 2 (/wall): its field corners: list[Corner] has no ROS type" in text
    assert "\n" not in text


def test_a_type_nobody_declares_is_the_unknown_ros_type_line():
    with pytest.raises(msgspec.ValidationError, match="unknown ROS type 'gen_msgs/msg/Readin' for /r; did you mean"):
        row(key="r", ros="/r", type="gen_msgs/msg/Readin")


def test_a_type_is_found_in_the_module_its_package_names(tmp_path, monkeypatch):
    (tmp_path / "probe_msgs.py").write_text(
        textwrap.dedent(
            """
            from turtlectl import Message

            class Probe(Message, tag="Probe"):
                depth: float
            """
        )
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    found = ros2_generic.user_type("probe_msgs/msg/Probe")
    assert found is not None and found.__name__ == "Probe"
    assert ros2_generic.user_type("probe_msgs/msg/Other") is None
    assert ros2_generic.user_type("turtlectl/msg/Pose") is None  # turtlectl's own are built-ins
