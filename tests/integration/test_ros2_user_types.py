"""A user's own flat message type across the ROS 2 bridge, both ways, in a network namespace holding
only loopback (tests/integration/ros2_side.py): a user node's messages arrive at a plain Cyclone DDS
reader of the type (what a ROS 2 node built with its ``.msg`` reads), a Cyclone writer's samples arrive
in ``turtlectl echo`` as the user's type; a type that cannot cross is one line at ``launch --check``."""

from __future__ import annotations

import json
import subprocess
import textwrap
from pathlib import Path

import pytest

from tests.integration.harness import turtlectl
from tests.integration.ros2_side import SCRIPTS, ros_env, ros_side

pytestmark = pytest.mark.integration

READING_MSGS = textwrap.dedent(
    '''
    import msgspec

    from turtlectl import Message


    class Reading(Message, tag="Reading"):
        """A sensor reading: flat, so it crosses to ROS 2."""

        value: float  # V: what was read
        label: str = ""  # -: which sensor
        samples: list[float] = []  # V: the last ones
        stamp: int = 0  # ns: when it was published
        seq: int = 0  # -: per-publisher count


    class Corner(msgspec.Struct, frozen=True):
        x: float


    class Walls(Message, tag="Walls"):
        """Not flat: a list of Structs."""

        corners: list[Corner] = []  # m: the corners seen
    '''
)

SENSOR = textwrap.dedent(
    """
    import msgspec

    from reading_msgs import Reading


    class Sensor:
        Params = msgspec.defstruct("SensorParams", [])

        def __init__(self, node):
            pub = node.publisher("sensor/reading", Reading)
            node.timer(0.1, lambda: pub.publish(Reading(value=3.25, label="left", samples=[1.0, 2.5])))
    """
)

LAUNCH = """
[[node]]
name = "sensor"
run = "./sensor.py:Sensor"

[[node]]
name = "ros2_bridge"
run = "ros2_bridge"
params.defaults = false

[[node.params.topics]]
key = "sensor/reading"
ros = "/reading"
type = "reading_msgs/msg/Reading"

[[node.params.topics]]
key = "reading_in"
ros = "/reading_in"
type = "reading_msgs/msg/Reading"
direction = "from_ros"
"""


def project(folder: Path, launch: str = LAUNCH) -> Path:
    (folder / "reading_msgs.py").write_text(READING_MSGS)
    (folder / "sensor.py").write_text(SENSOR)
    (folder / "launch.toml").write_text(launch)
    return folder


def test_a_users_flat_type_crosses_both_ways(tmp_path):
    folder = project(tmp_path)
    script = str(SCRIPTS / "dds_generic.py")
    with ros_side() as side:
        side.launch(LAUNCH, folder, nodes=2)
        reader = side.turtlectl_python(
            script, "read", "/reading", str(folder), "reading_msgs/msg/Reading", env=ros_env()
        )
        reader.wait_for("^READY$")
        got = reader.json_line("MSG")
        assert (got["value"], got["label"], got["samples"]) == (3.25, "left", [1.0, 2.5])
        assert got["seq"] > 0 and got["stamp"] > 0  # the user's publisher stamped it
        sample = json.dumps({"value": -1.5, "label": "from ros", "samples": [4.0]})
        writer = side.turtlectl_python(
            script, "write", "/reading_in", str(folder), "reading_msgs/msg/Reading", sample, env=ros_env()
        )
        writer.wait_for("^READY$")
        done = side.tool("echo", "reading_in", "--once", "--json")
        assert done.returncode == 0, done.stdout + done.stderr
        echoed = json.loads(done.stdout)
        assert echoed["type"] == "reading_msgs/Reading", echoed
        assert (echoed["value"], echoed["label"], echoed["samples"]) == (-1.5, "from ros", [4.0])


def test_a_users_type_that_is_not_flat_is_one_line_at_check(tmp_path):
    folder = project(
        tmp_path,
        LAUNCH.replace(
            'ros = "/reading"\ntype = "reading_msgs/msg/Reading"', 'ros = "/reading"\ntype = "reading_msgs/msg/Walls"'
        ),
    )
    done = subprocess.run(
        [*turtlectl(), "launch", str(folder / "launch.toml"), "--check"], capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 2, done.stdout + done.stderr
    assert done.stderr.strip().count("\n") == 0, done.stderr
    assert (
        "reading_msgs/Walls cannot cross to ROS 2 (/reading): its field corners: list[Corner] has no ROS type"
        in done.stderr
    )
