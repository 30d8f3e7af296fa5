"""What writing a message costs in a ROS 2 bag (``record --profile ros2``: CDR through rosbags) and in
turtlectl's own recording, per message, on this machine's CPU.  No network.  Needs the ros2 extra.

    .venv/bin/python bench/ros2_bag_write.py [COUNT]
"""

import math
import sys
import tempfile
import time
from pathlib import Path

from turtlectl.cli.recording.bag import BagWriter
from turtlectl.cli.recording.ros2bag import Ros2BagWriter
from turtlectl.messages import LaserScan, Pose, encode, encoding_for


def main() -> int:
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 2000
    beams = [1.0] * 360
    samples = [
        ("Pose", encode(Pose(x=1.0, y=2.0, theta=0.5)), encoding_for(Pose)),
        (
            "LaserScan (360 beams)",
            encode(
                LaserScan(
                    angle_min=-math.pi,
                    angle_max=math.pi,
                    angle_increment=math.pi / 180,
                    range_min=0.1,
                    range_max=4.0,
                    ranges=beams,
                )
            ),
            encoding_for(LaserScan),
        ),
    ]
    folder = Path(tempfile.mkdtemp())
    for profile, writer in (("ros2", Ros2BagWriter(folder / "bag")), ("turtlectl", BagWriter(folder / "run.mcap"))):
        for what, payload, encoding in samples:
            start = time.perf_counter()
            for i in range(count):
                writer.add(f"bench/{what[:4]}", encoding, payload, 1_700_000_000_000_000_000 + i)
            print(f"{profile:10s} {what:22s} {(time.perf_counter() - start) / count * 1e6:7.1f} us per message")
        writer.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
