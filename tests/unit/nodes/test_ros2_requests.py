"""The pure part of calling ROS 2 services: the type table, the DDS names, the request a user types."""

from __future__ import annotations

import math

import pytest

from turtlectl.nodes import ros2_requests as rq


def test_the_dds_names_are_what_a_fast_dds_server_matches():
    assert rq.service_topics("/set_flag") == ("rq/set_flagRequest", "rr/set_flagReply")
    assert rq.service_topics("turtle1/teleport_absolute") == (
        "rq/turtle1/teleport_absoluteRequest",
        "rr/turtle1/teleport_absoluteReply",
    )
    assert rq.request_type_name("std_srvs/srv/SetBool") == "std_srvs::srv::dds_::SetBool_Request_"
    assert rq.response_type_name("turtlesim/srv/Spawn") == "turtlesim::srv::dds_::Spawn_Response_"


@pytest.mark.parametrize("name", ["", "/", "/a//b", "/1abc", "/a-b", "/a b"])
def test_a_name_that_is_no_ros_name_is_refused(name):
    with pytest.raises(ValueError, match="is no ROS service name"):
        rq.check_service_name(name)


def test_every_type_has_ros_primitive_fields_and_an_empty_side_has_the_placeholder():
    for request, response in rq.SERVICE_TYPES.values():
        assert all(kind in rq.PRIMITIVES for _, kind in request + response)
    assert rq.wire_fields(()) == ((rq.PLACEHOLDER, "uint8"),)
    assert rq.wire_fields((("data", "bool"),)) == (("data", "bool"),)


def test_an_unknown_type_names_the_known_ones():
    with pytest.raises(ValueError, match=r"unknown service type 'std_srvs/srv/Nope' \(known: std_srvs/srv/Empty, "):
        rq.check_service_type("std_srvs/srv/Nope")


@pytest.mark.parametrize(
    ("text", "fields"),
    [
        ("", {}),
        ("{}", {}),
        ("{data: true}", {"data": True}),
        ("data: false", {"data": False}),
        ('{"data": true}', {"data": True}),
        ("{x: 1.5, y: 2, theta: -0.5, name: 'a, b'}", {"x": 1.5, "y": 2, "theta": -0.5, "name": "a, b"}),
        ('{name: "t2"}', {"name": "t2"}),
        ("{name: t2}", {"name": "t2"}),
        ("{x: .inf}", {"x": math.inf}),
    ],
)
def test_a_request_is_read_as_ros2_service_call_reads_it(text, fields):
    assert rq.parse_request(text) == fields


@pytest.mark.parametrize("text", ["{data}", "[1, 2]", "{a: {b: 1}}", "true"])
def test_a_request_that_is_no_mapping_is_refused(text):
    with pytest.raises(ValueError, match="request"):
        rq.parse_request(text)


def test_a_request_is_fitted_to_its_type_with_defaults_in_srv_order():
    assert rq.fit_request("std_srvs/srv/SetBool", {}) == {"data": False}
    assert rq.fit_request("std_srvs/srv/Empty", {}) == {}
    assert rq.fit_request("turtlesim/srv/Spawn", {"name": "t2", "x": 1}) == {
        "x": 1.0,
        "y": 0.0,
        "theta": 0.0,
        "name": "t2",
    }
    assert rq.fit_request("turtlesim/srv/SetPen", {"r": 255, "width": 3.0}) == {
        "r": 255,
        "g": 0,
        "b": 0,
        "width": 3,
        "off": 0,
    }


@pytest.mark.parametrize(
    ("ros_type", "values", "message"),
    [
        ("std_srvs/srv/SetBool", {"flag": True}, "std_srvs/srv/SetBool has no request field 'flag' (its fields: data)"),
        ("std_srvs/srv/Trigger", {"data": True}, "std_srvs/srv/Trigger has no request field 'data' (it has no fields)"),
        ("std_srvs/srv/SetBool", {"data": 1}, "std_srvs/srv/SetBool field 'data' (bool) takes true or false, not 1"),
        ("turtlesim/srv/Kill", {"name": 3}, "turtlesim/srv/Kill field 'name' (string) takes a string, not 3"),
        ("turtlesim/srv/Spawn", {"x": "a"}, "turtlesim/srv/Spawn field 'x' (float32) takes a number, not 'a'"),
        ("turtlesim/srv/Spawn", {"x": True}, "turtlesim/srv/Spawn field 'x' (float32) takes a number, not True"),
        (
            "turtlesim/srv/SetPen",
            {"r": 256},
            "turtlesim/srv/SetPen field 'r' (uint8) takes a whole number from 0 to 255, not 256",
        ),
        ("turtlesim/srv/SetPen", {"r": 1.5}, "turtlesim/srv/SetPen field 'r' (uint8) takes a whole number, not 1.5"),
    ],
)
def test_a_request_that_does_not_fit_says_which_field_and_why(ros_type, values, message):
    with pytest.raises(ValueError) as caught:
        rq.fit_request(ros_type, values)
    assert str(caught.value) == message


def test_the_dds_structs_serialize_as_ros_cdr():
    from turtlectl.nodes import ros2_services

    request, response = ros2_services.idl_types("std_srvs/srv/SetBool")
    assert request.__name__ == "SetBool_Request" and response().message == ""
    assert request(data=True).serialize() == b"\x00\x01\x00\x00\x01"  # CDR little endian, then one bool
    empty, _ = ros2_services.idl_types("std_srvs/srv/Empty")
    assert empty().serialize() == b"\x00\x01\x00\x00\x00"  # the placeholder byte
    spawn, _ = ros2_services.idl_types("turtlesim/srv/Spawn")
    assert spawn.deserialize(spawn(x=1.5, name="t2").serialize()) == spawn(x=1.5, y=0.0, theta=0.0, name="t2")
