"""cli.tools.build: messages and requests from JSON, with the bad field named."""

import pytest

from turtlectl.cli.tools.build import message_from_json, service_request, topic_message
from turtlectl.messages import (
    Cancel,
    Pose,
    TeleportAbsolute,
    Twist,
)
from turtlectl.runtime.client.errors import BadInput, ExitCode, TurtlectlError, exit_code


def test_messages_from_json_name_the_bad_field():
    assert topic_message("turtle1/cmd_vel", '{"linear": 1}') == Twist(linear=1.0)
    with pytest.raises(BadInput, match="linear: Expected `float`, got `str`"):
        topic_message("turtle1/cmd_vel", '{"linear": "x"}')
    with pytest.raises(BadInput, match="unknown field `boost`"):
        message_from_json('{"boost": 1}', Twist)
    with pytest.raises(BadInput, match="--type"):
        topic_message("some/key", "{}")
    assert service_request("turtle1/teleport_absolute", '{"x":1,"y":2,"theta":0}') == TeleportAbsolute(
        x=1, y=2, theta=0
    )
    assert service_request("turtlectl/params/sim", "{}") == b"{}"
    with pytest.raises(BadInput, match="not valid JSON"):
        service_request("any/key", "{")


def test_a_known_key_keeps_its_type():
    assert type(topic_message("turtle1/cmd_vel", "{}", "Twist")) is Twist
    assert type(topic_message("some/topic", '{"x": 1, "y": 2, "theta": 0}', "Pose")) is Pose
    with pytest.raises(TurtlectlError) as err:
        topic_message("turtle1/cmd_vel", '{"x": 1, "y": 2, "theta": 0}', "Pose")
    assert (
        exit_code(err.value) == ExitCode.BAD_INPUT
        and "turtle1/cmd_vel carries turtlectl/Twist, not turtlectl/Pose" in err.value.message
    )
    with pytest.raises(TurtlectlError, match="navigate_to/cancel takes turtlectl/Cancel, not turtlectl/Pose"):
        service_request("navigate_to/cancel", '{"x": 1, "y": 2, "theta": 0}', "Pose")
    assert type(service_request("navigate_to/cancel", "{}", "Cancel")) is Cancel


def test_the_services_every_node_has_take_their_own_request_types():
    """`call turtlectl/params/navigator/set '{...}'` needs no --type."""
    from turtlectl.messages import SetLogLevel, SetParameter

    assert service_request("turtlectl/params/navigator/set", '{"name": "goal_timeout", "value": 60}') == SetParameter(
        name="goal_timeout", value=60
    )
    assert service_request("turtlectl/nodes/sim/log_level", '{"level": "DEBUG"}') == SetLogLevel(level="DEBUG")
    assert service_request("turtlectl/params/sim", "{}") == b"{}"  # the JSON answer: no type
