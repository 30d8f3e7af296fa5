"""What code cannot say about the wire contract's types, in one place: the unit, range and
meaning of every field of every message type (each key's use: messages.key_reference).
Read by ``turtlectl interface`` and by docs/gen_interfaces.py (docs/interfaces.md);
tests/unit/docs/test_gen_interfaces.py fails when a field has no entry here, or an entry
names one that no longer exists.  Pure data: no zenoh (a field as text: messages.fieldtext).
"""

from __future__ import annotations

from turtlectl.messages import GoalState

STAMP = (
    "ns",
    ">= 0",
    "time at publishing, ns since the Unix epoch: the wall clock's, or the simulated clock's for a node with "
    "use_sim_time (0 if the sender did not stamp it)",
)
SEQ = ("count", ">= 0", "per-publisher counter from 0; starts again at 0 when the publisher restarts")

# (type, field) -> (unit, range or values, meaning).  Every field of every wire type.
FIELDS: dict[str, dict[str, tuple[str, str, str]]] = {
    "Twist": {
        "linear": (
            "m/s",
            "any finite value; the sim clamps it to [-max_linear_speed, max_linear_speed] and ramps at max_linear_accel; non-finite stops the turtle",
            "speed along the heading; negative drives backwards",
        ),
        "angular": (
            "rad/s",
            "any finite value; the sim clamps it to [-max_angular_speed, max_angular_speed] and ramps at max_angular_accel",
            "yaw rate, counter-clockwise positive",
        ),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "Pose": {
        "x": ("m", "[0, world size]", "position in the world frame"),
        "y": ("m", "[0, world size]", "position in the world frame"),
        "theta": ("rad", "[-pi, pi)", "heading; 0 along +x, counter-clockwise positive"),
        "linear_velocity": ("m/s", "[-max_linear_speed, max_linear_speed]", "speed along the heading"),
        "angular_velocity": ("rad/s", "[-max_angular_speed, max_angular_speed]", "yaw rate"),
        "contact": (
            "-",
            "true / false",
            "the turtle touches a declared obstacle or another turtle (it stops there, as at a wall)",
        ),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "TurtleStatus": {
        "x": ("m", "[0, world size]", "position"),
        "y": ("m", "[0, world size]", "position"),
        "theta": ("degrees", "[0, 360)", "heading; 0 along +x, counter-clockwise positive"),
        "vel_x": ("m/s", "any", "velocity along the world's x axis"),
        "vel_y": ("m/s", "any", "velocity along the world's y axis"),
        "battery": ("%", "[0, 100]", "simulated charge; drains with time and distance, full after a reset"),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "LaserScan": {
        "angle_min": (
            "rad",
            "[-pi, pi]",
            "angle of beam 0, relative to the heading at origin_theta (0 = straight ahead, CCW positive)",
        ),
        "angle_max": ("rad", "angle_min + at most 2 pi", "angle of the last beam, relative to the heading"),
        "angle_increment": (
            "rad",
            ">= 0",
            "between consecutive beams: beam i points at angle_min + i * angle_increment",
        ),
        "range_min": ("m", ">= 0", "shortest range the sensor reports"),
        "range_max": ("m", "> range_min", "longest range; farther hits are not reported"),
        "ranges": (
            "m",
            "[0, range_max] or inf",
            'one per beam: distance to the first hit, walls and declared obstacles (and phantoms) alike; inf = nothing within range_max ("Infinity" in JSON); 0 on every beam inside an obstacle',
        ),
        "origin_x": ("m", "[0, world size] or NaN", "where the scan was taken (the turtle's position); NaN if unknown"),
        "origin_y": ("m", "[0, world size] or NaN", "where the scan was taken; NaN if unknown"),
        "origin_theta": (
            "rad",
            "[-pi, pi) or NaN",
            "the turtle's heading when the scan was taken; world angle of beam i = origin_theta + angle_min + i * angle_increment",
        ),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "NavigateToRequest": {
        "x": (
            "m",
            "[0, world size], at least the navigator's robot_radius + clearance from every declared obstacle",
            "goal position",
        ),
        "y": (
            "m",
            "[0, world size], at least the navigator's robot_radius + clearance from every declared obstacle",
            "goal position",
        ),
        "theta": ("degrees", "any finite value (taken modulo 360)", "goal heading"),
        "client": (
            "-",
            "one key chunk, or empty",
            'id of the caller\'s liveliness token @turtlectl/client/<id>; when that token vanishes the goal is canceled ("caller gone"); empty: none',
        ),
    },
    "NavigateToFeedback": {
        "state": ("-", ", ".join(f'"{s.value}"' for s in GoalState), "what the turtle does now"),
        "distance_remaining": ("m", ">= 0", "distance to the goal position along the path"),
        "heading_remaining": (
            "degrees",
            "[0, 180]",
            "absolute difference between the heading now and the goal heading",
        ),
        "eta": ("s", ">= 0", "estimated time to arrival within the robot's limits"),
        "elapsed": ("s", ">= 0", "since the navigator received the goal"),
        "x": ("m", "[0, world size]", "position now"),
        "y": ("m", "[0, world size]", "position now"),
        "theta": ("degrees", "[0, 360)", "heading now"),
        "goal_x": ("m", "[0, world size]", "the goal being run"),
        "goal_y": ("m", "[0, world size]", "the goal being run"),
        "goal_theta": ("degrees", "[0, 360)", "the goal heading"),
        "scan_stale": (
            "-",
            "true / false",
            "no scan newer than the navigator's scan_timeout: it avoids only the declared obstacles",
        ),
        "path": (
            "m",
            "points (x, y) in the world",
            "the way the turtle follows, from where it was planned to the goal: a straight way is its two ends, "
            'arcs round obstacles a point every 10 degrees; empty while there is no way (state "replanning")',
        ),
        "replans": (
            "-",
            ">= 0",
            "times the path was planned again during this goal (something the scan sees in the way, or the turtle off its path)",
        ),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "NavigateToResponse": {
        "success": ("-", "true / false", "the goal was reached within position_tolerance and heading_tolerance"),
        "time_taken": ("s", ">= 0", "from the navigator receiving the request to this reply"),
        "reason": (
            "-",
            "text",
            'empty on success; else a short word for programs: "invalid goal", "unreachable" (no way round the declared obstacles; detail says why), "battery low", "preempted", "canceled", "caller gone", "teleported", "reset", "blocked", "no pose", "timeout", "navigator shut down"',
        ),
        "refused": (
            "-",
            "true / false",
            "the goal never started (invalid, unreachable, battery low); x, y, theta are where the turtle is",
        ),
        "position_error": ("m", ">= 0", "final distance to the goal position"),
        "heading_error": ("degrees", "[0, 180]", "final absolute heading error"),
        "x": ("m", "[0, world size]", "final position"),
        "y": ("m", "[0, world size]", "final position"),
        "theta": ("degrees", "[0, 360)", "final heading"),
        "detail": (
            "-",
            "text, or empty",
            "a sentence for people: why, and what to do next (e.g. the battery level and `turtlectl reset`, what blocked the way); not meant to be parsed",
        ),
    },
    "Cancel": {
        "reason": ("-", "text, or empty", 'what the canceled goal\'s caller is told (empty: "canceled")'),
        "detail": (
            "-",
            "text, or empty",
            "a sentence for people that the canceled goal's caller is told with the reason (empty: the server's own)",
        ),
    },
    "Moving": {
        "reason": (
            "-",
            '"teleported" or "reset"',
            "why the simulator is about to move the turtle (a running goal ends with it)",
        ),
    },
    "TeleportAbsolute": {
        "x": (
            "m",
            "[0, world size], not inside a declared obstacle (its centre), not within 2 turtle radii of another turtle",
            "new position",
        ),
        "y": (
            "m",
            "[0, world size], not inside a declared obstacle (its centre), not within 2 turtle radii of another turtle",
            "new position",
        ),
        "theta": (
            "rad",
            "any finite value (wrapped to [-pi, pi))",
            "new heading, radians as turtlesim's (turtlectl teleport takes degrees)",
        ),
    },
    "Reset": {},
    "SpawnRequest": {
        "x": ("m", "[0, world size], not inside a declared obstacle nor within 2 turtle radii of a turtle", "where"),
        "y": ("m", "[0, world size], not inside a declared obstacle nor within 2 turtle radii of a turtle", "where"),
        "theta": (
            "rad",
            "any finite value (wrapped to [-pi, pi))",
            "heading, radians as turtlesim's (turtlectl spawn takes degrees)",
        ),
        "name": (
            "-",
            "empty, or a letter or _ then letters, digits, _ or - (at most 63), not taken, not a first chunk of the system's keys (turtlectl, robot, navigate_to, obstacles, reset, spawn, kill, turtles, clock)",
            "the new turtle's name and its keys' first chunk (empty: the first free turtleN)",
        ),
    },
    "SpawnResponse": {"name": ("-", "text", "the new turtle's name")},
    "Turtles": {
        "names": ("-", "list of names", "every turtle in the world"),
        "x": ("m", "[0, world size] each", "their positions, in the order of names"),
        "y": ("m", "[0, world size] each", "their positions, in the order of names"),
        "theta": ("rad", "[-pi, pi) each", "their headings, in the order of names"),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "Clock": {
        "clock": (
            "ns",
            ">= 0",
            "the simulated time since the Unix epoch: the wall clock's when the simulator started, then one step (16 ms) per step",
        ),
        "real_time_factor": (
            "-",
            "> 0",
            "simulated seconds per wall-clock second the simulator aims at (its real_time_factor parameter)",
        ),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "Kill": {"name": ("-", "a turtle's name", "the turtle to remove")},
    "Ack": {
        "ok": ("-", "true / false", "the request was carried out (false: e.g. cancel with no goal running)"),
        "detail": ("-", "text", "a sentence for people saying what was done; not meant to be parsed"),
    },
    "ErrorReply": {
        "error": (
            "-",
            "text",
            "why the request could not be used (undecodable, unknown field, missing field, impossible pose, a parameter that cannot change)",
        ),
    },
    "SetParameter": {
        "name": ("-", "a parameter of the node; dotted into a table (gains.lookahead)", "the parameter to change"),
        "value": (
            "the parameter's own",
            "what the launch file accepts for it (`turtlectl param describe NODE NAME`)",
            "the new value",
        ),
    },
    "ParameterEvent": {
        "node": ("-", "a node name", "the node whose parameter changed"),
        "name": ("-", "dotted (gains.lookahead)", "the parameter that changed"),
        "old_value": ("the parameter's own", "-", "its value before"),
        "new_value": ("the parameter's own", "-", "its value from now on"),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "SetLogLevel": {
        "level": (
            "-",
            "DEBUG, INFO, WARNING, ERROR (any case)",
            "the least severe log line the node writes from now on",
        ),
    },
    "Log": {
        "level": (
            "-",
            "10 DEBUG, 20 INFO, 30 WARNING, 40 ERROR, 50 CRITICAL (Python's and ROS's numbers; another number between them is a level of its own)",
            "how severe the record is; a node publishes the records at its log level and above",
        ),
        "node": ("-", "a node's full name (turtle2/navigator)", "the node that logged it"),
        "message": ("-", "any text, may span lines", "what was logged, with its traceback when it has one"),
        "file": ("-", "a path, or empty", "the source file that logged it"),
        "function": ("-", "a name, or empty", "the function that logged it"),
        "line": ("-", ">= 0 (0: unknown)", "the line in that file"),
        "stamp": ("ns", ">= 0", "when it was logged: wall-clock time, ns since the Unix epoch"),
        "seq": SEQ,
    },
    "String": {
        "data": ("-", "any text", "the text (an rclpy talker's std_msgs/String, through the ROS 2 bridge)"),
        "stamp": STAMP,
        "seq": SEQ,
    },
}
