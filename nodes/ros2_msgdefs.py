"""The ``.msg`` definitions of the ROS 2 types turtlectl defines itself (no ROS package ships them).

Pure data.  ``turtlesim/msg/Pose`` is turtlesim's own definition, field for field; the capstone's
``capstone_msgs/msg/TurtleStatus`` is docs/capstone.md's status (turtlectl.messages.TurtleStatus
without its stamp and seq).  The standard types (geometry_msgs, sensor_msgs, ...) are not here:
a ROS library's own definitions are used for them (rosbags' typestore for ROS 2 Kilted).
"""

from __future__ import annotations

TURTLESIM_POSE = """\
float32 x
float32 y
float32 theta

float32 linear_velocity
float32 angular_velocity
"""

TURTLE_STATUS = """\
# The capstone's robot status, 10 Hz: position m, heading degrees [0, 360), velocity in the world frame m/s,
# battery percent [0, 100]
float64 x
float64 y
float64 theta
float64 vel_x
float64 vel_y
float64 battery
"""

#: ROS type name -> its .msg text
OWN: dict[str, str] = {
    "turtlesim/msg/Pose": TURTLESIM_POSE,
    "capstone_msgs/msg/TurtleStatus": TURTLE_STATUS,
}
