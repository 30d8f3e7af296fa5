"""This project's message types, as a ROS 2 interfaces package would hold them: the lesson's
``TurtleStatus``.  Its full name is ``capstone_msgs/TurtleStatus`` (the package is this module's
name), so it lives beside turtlectl's own ``turtlectl/TurtleStatus``."""

from __future__ import annotations

from turtlectl import Message


class TurtleStatus(Message, tag="TurtleStatus"):
    """The robot's state, published on robot/status at 10 Hz."""

    x: float  # m: position, east
    y: float  # m: position, north
    theta: float  # degrees: heading, [0, 360)
    vel_x: float  # m/s: velocity along x
    vel_y: float  # m/s: velocity along y
    battery: float  # %: simulated charge, [0, 100]
    stamp: int = 0  # ns: when it was published (filled in by the publisher)
    seq: int = 0  # -: per-publisher count (filled in by the publisher)
