"""The navigator process: serves ``navigate_to`` and drives the turtle there.

One goal at a time: a new goal preempts the running one (its caller gets
success=false, reason "preempted").  On each pose the control law
(nodes.control) gives a velocity; the navigator stops the turtle while the
latest scan shows an obstacle within the safety distance in its direction of
travel, and publishes ``turtle1/cmd_vel`` only while a goal is active.
"""

from __future__ import annotations

import math
import time

import numpy as np

from messages import LaserScan, NavigateToRequest, NavigateToResponse, Pose, Twist
from messages.keys import CMD_VEL, NAVIGATE_TO, OBSTACLES, POSE
from nodes.control import Phase, control_step
from nodes.goal import goal_problem, heading_error_deg, stopping_margin
from nodes.params import NavigatorParams
from nodes.runtime import Node, Request, run
from nodes.scan import nearest_in_cone

WATCHDOG_PERIOD = 0.05  # s


class Goal:
    def __init__(self, request: Request[NavigateToRequest]):
        self.request = request
        self.x = request.body.x
        self.y = request.body.y
        self.theta = math.radians(request.body.theta)
        self.start = time.monotonic()
        self.phase = Phase.DRIVE
        self.blocked_since: float | None = None


class Navigator:
    def __init__(self, node: Node[NavigatorParams]):
        self.node = node
        self.pose: Pose | None = None
        self.pose_time = 0.0
        self.scan: LaserScan | None = None
        self.scan_angles = np.zeros(0)
        self.scan_time = 0.0
        self.scan_period = 0.2  # s, refined from arrivals
        self.goal: Goal | None = None
        self.cmd_pub = node.publisher(CMD_VEL, Twist)
        node.subscribe(POSE, Pose, self.on_pose)
        node.subscribe(OBSTACLES, LaserScan, self.on_scan)
        node.serve(NAVIGATE_TO, NavigateToRequest, NavigateToResponse, self.on_goal)
        node.timer(WATCHDOG_PERIOD, self.watchdog)
        node.on_shutdown(lambda: self.finish(False, "navigator shut down"))

    # -- inputs -------------------------------------------------------------
    def on_goal(self, request: Request[NavigateToRequest]) -> None:
        body = request.body
        problem = goal_problem(body, self.node.world)
        if problem is not None:
            self.node.log.info("refused goal (%g, %g, %g deg): %s", body.x, body.y, body.theta, problem)
            request.respond(NavigateToResponse(success=False, time_taken=0.0, reason=problem))
            return
        self.finish(False, "preempted")
        self.goal = Goal(request)
        self.node.log.info("goal (%.3f, %.3f, %.1f deg)", body.x, body.y, body.theta)
        self.drive()

    def on_pose(self, pose: Pose) -> None:
        self.pose, self.pose_time = pose, time.monotonic()
        self.drive()

    def on_scan(self, scan: LaserScan) -> None:
        now = time.monotonic()
        if self.scan is not None:
            self.scan_period = 0.8 * self.scan_period + 0.2 * min(now - self.scan_time, 1.0)
        if self.scan is None or len(scan.ranges) != len(self.scan.ranges) or scan.angle_min != self.scan.angle_min:
            self.scan_angles = scan.angle_min + scan.angle_increment * np.arange(len(scan.ranges))
        self.scan, self.scan_time = scan, now

    def watchdog(self) -> None:
        goal = self.goal
        if goal is None:
            return
        now = time.monotonic()
        p = self.node.params
        if now - goal.start > p.goal_timeout:
            self.finish(False, "timeout")
        elif now - max(self.pose_time, goal.start) > p.pose_timeout:
            self.finish(False, "no pose")

    # -- control ------------------------------------------------------------
    def drive(self) -> None:
        goal, pose = self.goal, self.pose
        if goal is None or pose is None:
            return
        p = self.node.params
        cmd = control_step(
            pose.x,
            pose.y,
            pose.theta,
            goal.x,
            goal.y,
            goal.theta,
            goal.phase,
            self.node.limits,
            p.gains,
            p.position_tolerance,
            math.radians(p.heading_tolerance),
        )
        goal.phase = cmd.phase
        if cmd.phase is Phase.DONE:
            self.finish(True, "")
            return
        if cmd.linear != 0.0 and self.blocked(cmd.linear, math.hypot(goal.x - pose.x, goal.y - pose.y)):
            now = time.monotonic()
            if goal.blocked_since is None:
                goal.blocked_since = now
                self.node.log.info("obstacle within %.2f m ahead: stopped", p.safety_distance)
            self.cmd_pub.publish(Twist())
            if now - goal.blocked_since > p.blocked_timeout:
                self.finish(False, "blocked")
            return
        if goal.blocked_since is not None:
            goal.blocked_since = None
            self.node.log.info("way clear: resuming")
        self.cmd_pub.publish(Twist(linear=cmd.linear, angular=cmd.angular))

    def blocked(self, linear: float, distance_to_goal: float) -> bool:
        """True if the latest scan shows an obstacle too close in the direction of travel."""
        if self.scan is None:
            return False
        p = self.node.params
        direction = 0.0 if linear > 0 else math.pi
        nearest = nearest_in_cone(
            np.asarray(self.scan.ranges), self.scan_angles, direction, math.radians(p.safety_cone)
        )
        margin = stopping_margin(linear, time.monotonic() - self.scan_time, self.scan_period)
        return nearest - margin < min(p.safety_distance, distance_to_goal)

    def finish(self, success: bool, reason: str) -> None:
        """End the running goal (if any): stop the turtle and answer its caller."""
        goal, self.goal = self.goal, None
        if goal is None:
            return
        self.cmd_pub.publish(Twist())
        pose = self.pose
        response = NavigateToResponse(success=success, time_taken=time.monotonic() - goal.start, reason=reason)
        if pose is not None:
            response.position_error = math.hypot(goal.x - pose.x, goal.y - pose.y)
            response.heading_error = heading_error_deg(goal.theta, pose.theta)
            response.x, response.y, response.theta = pose.x, pose.y, math.degrees(pose.theta) % 360.0
        level = self.node.log.info if success else self.node.log.warning
        level(
            "goal %s in %.3f s (error %.4f m, %.2f deg)%s",
            "reached" if success else "failed",
            response.time_taken,
            response.position_error,
            response.heading_error,
            f": {reason}" if reason else "",
        )
        goal.request.respond(response)


def main() -> None:
    run(Navigator, NavigatorParams)


if __name__ == "__main__":
    main()
