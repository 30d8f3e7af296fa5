"""Navigator: serves ``navigate_to`` as a goal service and drives the turtle straight to each
goal, then turns it to the goal's heading (the lesson's go-to-goal controller).

The goal server does the protocol: one goal at a time (a new one preempts), ``navigate_to/cancel``,
a caller that goes away, the ``goal_timeout`` deadline, feedback at 10 Hz, one result per goal.
This class only says how to drive, what progress to report and what to answer."""

from __future__ import annotations

import math
from typing import Annotated

import msgspec

from turtlectl import Interface, Node, run_main
from turtlectl.messages import (
    GoalState,
    LaserScan,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    Twist,
)


class NavigatorParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    max_speed: Annotated[float, msgspec.Meta(gt=0.0, le=4.0)] = 4.0  # m/s: fastest forward speed
    max_turn: Annotated[float, msgspec.Meta(gt=0.0, le=6.2832)] = 6.2832  # rad/s: fastest yaw rate
    brake: Annotated[float, msgspec.Meta(gt=0.0, le=10.0)] = 8.0  # m/s^2: how hard it slows down to arrive
    turn_brake: Annotated[float, msgspec.Meta(gt=0.0, le=40.0)] = 30.0  # rad/s^2: how hard it stops turning
    position_tolerance: Annotated[float, msgspec.Meta(gt=0.0, le=1.0)] = 0.05  # m: near enough the goal
    heading_tolerance: Annotated[float, msgspec.Meta(gt=0.0, le=45.0)] = 2.0  # degrees: near enough its heading
    stop_distance: Annotated[float, msgspec.Meta(ge=0.0, le=5.0)] = 0.4  # m: stop for a detection this close ahead
    goal_timeout: Annotated[float, msgspec.Meta(gt=0.0, le=3600.0)] = 30.0  # s: a goal ends "timeout" after it


def angle_to(a: float) -> float:
    """``a`` rad wrapped to [-pi, pi)."""
    return (a + math.pi) % (2 * math.pi) - math.pi


def stopping_speed(distance: float, brake: float, fastest: float) -> float:
    """The fastest speed from which ``brake`` still stops within ``distance`` (any unit per s)."""
    return min(fastest, math.sqrt(2.0 * brake * distance))


def command(pose: Pose, goal: NavigateToRequest, p: NavigatorParams) -> Twist | None:
    """The next velocity command towards ``goal`` (theta in degrees), or None once there: drive
    at the goal while farther than position_tolerance (turning first if it is behind), then
    turn on the spot to the goal's heading."""
    dx, dy = goal.x - pose.x, goal.y - pose.y
    distance = math.hypot(dx, dy)
    if distance > p.position_tolerance:
        error = angle_to(math.atan2(dy, dx) - pose.theta)
    else:
        error = angle_to(math.radians(goal.theta) - pose.theta)
        if abs(error) <= math.radians(p.heading_tolerance):
            return None
        distance = 0.0
    turn = math.copysign(stopping_speed(abs(error), p.turn_brake, p.max_turn), error)
    speed = stopping_speed(distance, p.brake, p.max_speed) * max(0.0, math.cos(error)) ** 4
    return Twist(linear=speed, angular=turn)


def blocked_ahead(scan: LaserScan, distance: float, cone: float = math.radians(30.0)) -> bool:
    """Something within ``distance`` m of the turtle, within ``cone`` rad of straight ahead."""
    return any(
        r < distance for i, r in enumerate(scan.ranges) if abs(scan.angle_min + i * scan.angle_increment) <= cone
    )


class Navigator:
    Params = NavigatorParams
    Interface = Interface(
        publishes=("turtle1/cmd_vel",),
        subscribes=("turtle1/pose", "obstacles"),
        goals=("navigate_to",),  # the goal service, its cancel and feedback, its callers' tokens
    )

    def __init__(self, node: Node[NavigatorParams]):
        self.node = node
        self.scans = 0  # obstacle messages received
        self.blocked = False
        self.cmd = node.publisher("turtle1/cmd_vel", Twist)
        self.pose = node.latest("turtle1/pose", Pose, follow=True)
        node.subscribe("obstacles", LaserScan, self.on_scan)
        self.goals = node.goal_server(
            "navigate_to",
            NavigateToRequest,
            NavigateToFeedback,
            NavigateToResponse,
            execute=self.execute,
            on_cancel=self.ended,
            feedback=self.progress,
            timeout=node.params.goal_timeout,
        )
        node.on_params(lambda p: setattr(self.goals, "timeout", p.goal_timeout))

    def execute(self, goal) -> None:
        """A goal accepted: a first step from the newest pose, then one with every pose (``on_pose``)."""
        self.node.log.info("goal (%.2f, %.2f, %.1f deg)", goal.request.x, goal.request.y, goal.request.theta)
        self.pose.each(self.on_pose)
        pose = self.pose.get()
        if pose is not None:
            self.on_pose(pose)

    def on_pose(self, pose: Pose) -> None:
        goal = self.goals.goal
        if goal is None:
            return
        twist = command(pose, goal.request, self.node.params)
        if twist is None:
            self.stop()
            goal.finish(self.result(goal, pose, success=True))
            self.node.log.info("goal reached in %.3f s", self.node.clock() - goal.started)
        else:
            self.cmd.publish(Twist(linear=0.0, angular=twist.angular) if self.blocked else twist)

    def on_scan(self, scan: LaserScan) -> None:
        self.scans += 1
        self.blocked = blocked_ahead(scan, self.node.params.stop_distance)
        self.node.log.debug("scan %d: %s", self.scans, "blocked ahead" if self.blocked else "clear ahead")

    def progress(self, goal) -> NavigateToFeedback | None:
        pose = self.pose.get()
        if pose is None:
            return None
        distance = math.hypot(goal.request.x - pose.x, goal.request.y - pose.y)
        heading = abs(angle_to(math.radians(goal.request.theta) - pose.theta))
        driving = distance > self.node.params.position_tolerance
        return NavigateToFeedback(
            state=GoalState.BLOCKED if self.blocked else GoalState.DRIVING if driving else GoalState.TURNING,
            distance_remaining=distance,
            heading_remaining=math.degrees(heading),
            eta=distance / self.node.params.max_speed,
            elapsed=self.node.clock() - goal.started,
            x=pose.x,
            y=pose.y,
            theta=math.degrees(pose.theta) % 360.0,
            goal_x=goal.request.x,
            goal_y=goal.request.y,
            goal_theta=goal.request.theta % 360.0,
        )

    def ended(self, goal, reason: str) -> NavigateToResponse:
        """The server ends the goal (canceled, preempted, caller gone, timeout): stop, and answer."""
        self.stop()
        self.node.log.warning("goal ended: %s", reason)
        return self.result(goal, self.pose.get(), success=False, reason=reason)

    def result(self, goal, pose: Pose | None, success: bool, reason: str = "") -> NavigateToResponse:
        where = {}
        if pose is not None:
            heading_error = abs(angle_to(math.radians(goal.request.theta) - pose.theta))
            where = {"x": pose.x, "y": pose.y, "theta": math.degrees(pose.theta) % 360.0}
            where["position_error"] = math.hypot(goal.request.x - pose.x, goal.request.y - pose.y)
            where["heading_error"] = math.degrees(heading_error)
        time_taken = self.node.clock() - goal.started
        return NavigateToResponse(success=success, time_taken=time_taken, reason=reason, **where)

    def stop(self) -> None:
        self.pose.each(None)
        self.cmd.publish(Twist(linear=0.0, angular=0.0))


if __name__ == "__main__":
    run_main(Navigator, NavigatorParams)
