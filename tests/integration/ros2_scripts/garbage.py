"""A DDS writer (Cyclone, turtlectl's .venv) of samples on TOPIC that claim to be std_msgs/msg/String
but do not decode as one (bytes that are no UTF-8, where CDR's string is): what a broken ROS peer sends.
Its type information is String's, so that the bridge's Cyclone reader matches it (a Fast DDS peer's
would be ignored anyway: nodes.ros2_dds).

    garbage.py TOPIC COUNT       prints READY once a reader matched, SENT after COUNT samples
"""

import sys
import time
from dataclasses import dataclass, field

import cyclonedds.idl.types as t
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.annotations import final
from cyclonedds.pub import DataWriter
from cyclonedds.topic import Topic

from turtlectl.nodes import ros2_dds, ros2_types


@dataclass
@final
class NotAString(IdlStruct, typename="std_msgs::msg::dds_::String_"):
    data: t.sequence[t.uint8] = field(default_factory=lambda: [0xFF, 0xFE, 0x00])  # CDR: as a 2-byte string


def pose_as_string() -> None:
    """Give NotAString the XTypes type information of std_msgs/msg/String (Cyclone matches on it)."""
    ros2_types.String.__idl__.fill_type_data()
    NotAString.__idl__.populate()
    NotAString.__idl__._xt_data = ros2_types.String.__idl__._xt_data
    NotAString.__idl__._xt_bytedata = ros2_types.String.__idl__._xt_bytedata


def main() -> None:
    topic, count = sys.argv[1], int(sys.argv[2])
    pose_as_string()
    participant = ros2_dds.participant(ros2_dds.ros_domain_id())
    writer = DataWriter(
        participant,
        Topic(participant, ros2_types.dds_topic(topic), NotAString, qos=ros2_dds.RELIABLE),
        qos=ros2_dds.RELIABLE,
    )
    end = time.monotonic() + 30
    while writer.get_publication_matched_status().current_count < 1 and time.monotonic() < end:
        time.sleep(0.01)  # pacing: polling the match under a deadline
    print("READY", flush=True)
    for _ in range(count):
        writer.write(NotAString())
        time.sleep(0.05)  # pacing of the samples (20 Hz), not a readiness wait
    print("SENT", flush=True)
    time.sleep(1.0)  # let reliable repairs finish before the participant goes


if __name__ == "__main__":
    main()
