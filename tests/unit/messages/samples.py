"""One valid message of every type, for the messages tests (and the feedback the CLI tests show)."""

import math

from turtlectl.messages import (
    Ack,
    Cancel,
    Clock,
    ErrorReply,
    Kill,
    LaserScan,
    Log,
    Moving,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    ParameterEvent,
    Pose,
    Reset,
    SetLogLevel,
    SetParameter,
    SpawnRequest,
    SpawnResponse,
    TeleportAbsolute,
    Turtles,
    TurtleStatus,
    Twist,
)

SAMPLES = [
    Twist(linear=1.5, angular=-0.25, stamp=123, seq=4),
    Pose(x=1.0, y=2.0, theta=-3.0, linear_velocity=0.5, angular_velocity=0.1, stamp=5, seq=6),
    TurtleStatus(x=1.0, y=2.0, theta=359.5, vel_x=0.1, vel_y=-0.2, battery=87.5, stamp=7, seq=8),
    LaserScan(
        angle_min=-math.pi,
        angle_max=math.pi,
        angle_increment=0.1,
        range_min=0.0,
        range_max=10.0,
        ranges=[1.0, math.inf, 2.5],
        origin_x=5.0,
        origin_y=4.0,
        origin_theta=0.5,
        stamp=9,
        seq=10,
    ),
    NavigateToRequest(x=1.0, y=2.0, theta=90.0, client="42-abcd"),
    NavigateToFeedback(
        state="driving", distance_remaining=1.5, heading_remaining=10.0, eta=0.8, elapsed=0.2, x=1, y=2, theta=3
    ),
    NavigateToFeedback(
        state="replanning",
        distance_remaining=2.5,
        heading_remaining=1.0,
        eta=1.8,
        elapsed=0.5,
        x=1,
        y=2,
        theta=3,
        path=[(1.0, 2.0), (2.5, 3.25), (4.0, 2.0)],
        replans=3,
    ),  # fmt: skip
    Cancel(),
    Moving(reason="teleported"),
    TeleportAbsolute(x=1.0, y=2.0, theta=0.5),
    Reset(),
    SpawnRequest(x=1.0, y=2.0, theta=0.5, name="turtle2"),
    SpawnResponse(name="turtle2"),
    Turtles(names=["turtle1", "turtle2"], x=[1.0, 2.0], y=[3.0, 4.0], theta=[0.0, 1.0], stamp=5, seq=1),
    Clock(clock=1_764_100_000_000_000_000, real_time_factor=5.0),
    Kill(name="turtle2"),
    Ack(ok=False, detail="no goal is running"),
    NavigateToResponse(success=True, time_taken=1.25, position_error=0.004, heading_error=0.3, x=1, y=2, theta=90),
    ErrorReply(error="bad"),
    SetParameter(name="gains.lookahead", value=0.7),
    ParameterEvent(node="navigator", name="goal_timeout", old_value=30.0, new_value=60.0),
    SetLogLevel(level="DEBUG"),
    Log(
        level=30,
        node="turtle2/navigator",
        message="goal refused: battery low",
        file="/opt/turtlectl/nodes/navigator.py",
        function="on_goal",
        line=155,
        stamp=11,
        seq=12,
    ),
]


#: a running goal's feedback far from its goal, near 360 degrees
FEEDBACK = NavigateToFeedback(
    state="driving",
    distance_remaining=10.123,
    heading_remaining=179.9,
    eta=12.3,
    elapsed=14.5,
    x=11.08,
    y=11.08,
    theta=359.96,
    goal_x=1,
    goal_y=1,
    goal_theta=0,
)
