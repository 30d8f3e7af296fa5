"""A plain Cyclone DDS peer (turtlectl's .venv) of a user's own flat type: what a ROS 2 node built with
the type's ``.msg`` reads and writes (rclpy cannot import a type no package was built for).  The
struct is the bridge's generic one (nodes.ros2_dynamic), on its own participant (nodes.ros2_dds).

    dds_generic.py read TOPIC FOLDER ROS_TYPE           prints READY, then MSG <json> per sample
    dds_generic.py write TOPIC FOLDER ROS_TYPE JSON     prints READY once a reader matched, then
                                                        writes the sample every 0.1 s until stopped

FOLDER holds the user's module of the type (``reading_msgs.py`` for ``reading_msgs/msg/Reading``).
"""

import dataclasses
import json
import sys
import time

import msgspec
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from turtlectl.nodes import ros2_dds, ros2_dynamic, ros2_generic, ros2_types


def main() -> None:
    mode, topic, folder, ros_type = sys.argv[1:5]
    sys.path.insert(0, folder)
    cls = ros2_generic.user_type(ros_type)
    assert cls is not None, f"no {ros_type} in {folder}"
    struct = ros2_dynamic.idl_struct(cls)
    participant = ros2_dds.participant(ros2_dds.ros_domain_id())
    dds_topic = Topic(participant, ros2_types.dds_topic(topic), struct, qos=ros2_dds.RELIABLE)
    if mode == "read":
        reader = DataReader(participant, dds_topic, qos=ros2_dds.RELIABLE)
        print("READY", flush=True)
        while True:
            for sample in reader.take(N=16):
                if isinstance(sample, struct):
                    print("MSG", json.dumps(dataclasses.asdict(sample)), flush=True)
            time.sleep(0.01)  # pacing: polling the reader
    writer = DataWriter(participant, dds_topic, qos=ros2_dds.RELIABLE)
    end = time.monotonic() + 30
    while writer.get_publication_matched_status().current_count < 1 and time.monotonic() < end:
        time.sleep(0.01)  # pacing: polling the match under a deadline
    print("READY", flush=True)
    sample = ros2_dynamic.to_ros(msgspec.convert(json.loads(sys.argv[5]), cls))
    while True:
        writer.write(sample)
        time.sleep(0.1)  # the rate of the sample


if __name__ == "__main__":
    main()
