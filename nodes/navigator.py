"""The navigator process: serves ``navigate_to`` and drives the turtle there.

A goal's lifecycle, as Nav2's NavigateToPose:

* accepted (or refused at once: invalid, battery low), then fed back to its
  caller about 10 times a second (NavigateToFeedback replies), and ended by
  one NavigateToResponse: reached, or not with a reason;
* a new goal preempts the running one (reason "preempted"); ``navigate_to/cancel``
  cancels it ("canceled"); a caller whose liveliness token vanishes (Ctrl-C,
  kill -9) has its goal canceled ("caller gone"), so the turtle never drives
  for nobody; no pose for ``pose_timeout`` ends it ("no pose"), as does
  ``goal_timeout`` ("timeout") or ``blocked_timeout`` blocked ("blocked").

On each pose the control law (nodes.control) gives a velocity; the navigator
slows it for obstacles the latest scan shows in the direction of travel and
stops while one is within the safety distance.  It publishes
``turtle1/cmd_vel`` only while a goal runs.
"""

from __future__ import annotations

import math
import time

import numpy as np

from messages import (
    Ack,
    Cancel,
    LaserScan,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    TurtleStatus,
    Twist,
)
from messages.keys import CANCEL, CLIENT_TOKEN_PREFIX, CMD_VEL, FEEDBACK, NAVIGATE_TO, OBSTACLES, POSE, STATUS
from nodes.control import Phase, choose_direction, control_step, remaining_time
from nodes.goal import clearance_speed, goal_problem, heading_error_deg
from nodes.params import NavigatorParams
from nodes.runtime import Node, Request, run
from nodes.scan import corridor_clearance, hit_points, off_walls

WATCHDOG_PERIOD = 0.05  # s


class Goal:
    def __init__(self, request: Request[NavigateToRequest]):
        self.request = request
        body = request.body
        self.x, self.y, self.theta = body.x, body.y, math.radians(body.theta)
        self.client = f"{CLIENT_TOKEN_PREFIX}/{body.client}" if body.client else ""
        self.start = time.monotonic()
        self.phase = Phase.DRIVE
        self.direction = 0  # chosen with the first pose
        self.state = "turning"
        self.blocked_since: float | None = None


class Navigator:
    def __init__(self, node: Node[NavigatorParams]):
        self.node = node
        self.pose: Pose | None = None
        self.pose_time = 0.0
        self.battery: float | None = None
        self.scan_points = np.zeros((0, 2))  # world coordinates of the latest scan's hits, walls left out
        self.scan_time = 0.0
        self.goal: Goal | None = None
        self.cmd_pub = node.publisher(CMD_VEL, Twist)
        self.feedback_pub = node.publisher(FEEDBACK, NavigateToFeedback)
        node.subscribe(POSE, Pose, self.on_pose)
        node.subscribe(OBSTACLES, LaserScan, self.on_scan)
        node.subscribe(STATUS, TurtleStatus, self.on_status)
        node.serve(NAVIGATE_TO, NavigateToRequest, NavigateToResponse, self.on_goal)
        node.serve(CANCEL, Cancel, Ack, self.on_cancel)
        node.watch_liveliness(f"{CLIENT_TOKEN_PREFIX}/**", self.on_client)
        node.timer(WATCHDOG_PERIOD, self.watchdog)
        node.timer(1.0 / node.params.feedback_rate, self.feedback)
        node.on_shutdown(lambda: self.finish(False, "navigator shut down"))

    # -- inputs -------------------------------------------------------------
    def on_goal(self, request: Request[NavigateToRequest]) -> None:
        body = request.body
        problem = goal_problem(body, self.node.world)
        if problem is None and self.battery is not None and self.battery < self.node.params.min_battery:
            problem = "battery low"
        if problem is not None:
            self.node.log.info("refused goal (%g, %g, %g deg): %s", body.x, body.y, body.theta, problem)
            refusal = NavigateToResponse(success=False, time_taken=0.0, reason=problem, refused=True)
            if self.pose is not None:
                refusal.x, refusal.y = self.pose.x, self.pose.y
                refusal.theta = math.degrees(self.pose.theta) % 360.0
            request.respond(refusal)
            return
        self.finish(False, "preempted")
        self.goal = Goal(request)
        self.node.log.info("goal (%.3f, %.3f, %.1f deg)", body.x, body.y, body.theta)
        self.drive()

    def on_cancel(self, request: Request[Cancel]) -> None:
        if self.goal is None:
            request.respond(Ack(ok=False, detail="no goal is running"))
            return
        goal = self.goal
        self.finish(False, "canceled")
        request.respond(Ack(detail=f"canceled the goal ({goal.x:g}, {goal.y:g}, {math.degrees(goal.theta):g} deg)"))

    def on_client(self, key: str, alive: bool) -> None:
        if not alive and self.goal is not None and key == self.goal.client:
            self.finish(False, "caller gone")

    def on_pose(self, pose: Pose) -> None:
        self.pose, self.pose_time = pose, time.monotonic()
        self.drive()

    def on_status(self, status: TurtleStatus) -> None:
        self.battery = status.battery

    def on_scan(self, scan: LaserScan) -> None:
        origin = (scan.origin_x, scan.origin_y, scan.origin_theta)
        if not all(math.isfinite(v) for v in origin):  # a sensor that does not say where it was
            if self.pose is None:
                return
            origin = (self.pose.x, self.pose.y, self.pose.theta)
        angles = scan.angle_min + scan.angle_increment * np.arange(len(scan.ranges))
        points = hit_points(*origin, np.asarray(scan.ranges, dtype=float), angles)
        self.scan_points = off_walls(points, self.node.world.size)
        self.scan_time = time.monotonic()

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

    def feedback(self) -> None:
        goal, pose = self.goal, self.pose
        if goal is None or pose is None:
            return
        limits = self.node.limits
        eta = remaining_time(pose.x, pose.y, pose.theta, goal.x, goal.y, goal.theta, goal.direction or 1, limits)
        progress = self.feedback_pub.publish(  # for observers; the same, stamped, to the caller
            NavigateToFeedback(
                state=goal.state,
                distance_remaining=math.hypot(goal.x - pose.x, goal.y - pose.y),
                heading_remaining=heading_error_deg(goal.theta, pose.theta),
                eta=eta,
                elapsed=time.monotonic() - goal.start,
                x=pose.x,
                y=pose.y,
                theta=math.degrees(pose.theta) % 360.0,
                goal_x=goal.x,
                goal_y=goal.y,
                goal_theta=math.degrees(goal.theta),
            )
        )
        goal.request.respond(progress, final=False)

    # -- control ------------------------------------------------------------
    def drive(self) -> None:
        goal, pose = self.goal, self.pose
        if goal is None or pose is None:
            return
        p = self.node.params
        limits = self.node.limits
        if goal.direction == 0:
            goal.direction = choose_direction(pose.x, pose.y, pose.theta, goal.x, goal.y, goal.theta, limits)
        cmd = control_step(
            pose.x,
            pose.y,
            pose.theta,
            goal.x,
            goal.y,
            goal.theta,
            goal.phase,
            goal.direction,
            limits,
            p.gains,
            p.position_tolerance,
            math.radians(p.heading_tolerance),
        )
        goal.phase = cmd.phase
        if cmd.phase is Phase.DONE:
            self.finish(True, "")
            return
        linear = cmd.linear
        if linear != 0.0:
            allowed = self.obstacle_speed(pose, linear, math.hypot(goal.x - pose.x, goal.y - pose.y))
            linear = math.copysign(min(abs(linear), allowed), linear)
            if allowed == 0.0:
                self.blocked(goal, cmd.angular)
                return
        if goal.blocked_since is not None:
            goal.blocked_since = None
            self.node.log.info("way clear: resuming")
        goal.state = "driving" if linear != 0.0 else "turning"
        self.cmd_pub.publish(Twist(linear=linear, angular=cmd.angular))

    def blocked(self, goal: Goal, angular: float) -> None:
        """Something is too close in the direction of travel: do not drive, but keep turning
        (towards the goal, which may well lead away from it)."""
        now = time.monotonic()
        p = self.node.params
        if goal.blocked_since is None:
            goal.blocked_since = now
            self.node.log.info("obstacle within %.2f m in the direction of travel: stopped", p.safety_distance)
        goal.state = "blocked"
        self.cmd_pub.publish(Twist(linear=0.0, angular=angular))
        if now - goal.blocked_since > p.blocked_timeout:
            self.finish(False, "blocked")

    def obstacle_speed(self, pose: Pose, linear: float, distance_to_goal: float) -> float:
        """Fastest speed (m/s) allowed by the latest scan for travel in the direction of
        ``linear``; 0 while something between the turtle and its goal, inside the corridor
        along its path, is within the safety distance."""
        p = self.node.params
        if time.monotonic() - self.scan_time > p.scan_timeout:  # no recent scan: nothing known in the way
            return math.inf
        heading = pose.theta if linear > 0 else pose.theta + math.pi
        nearest = corridor_clearance(self.scan_points, pose.x, pose.y, heading, 0.5 * p.corridor_width)
        if nearest >= distance_to_goal:  # nothing before the goal
            return math.inf
        if nearest <= p.safety_distance:
            return 0.0
        return clearance_speed(nearest, p.safety_distance, p.obstacle_decel)

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
