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
slows it for obstacles in the direction of travel, the world's declared ones
always and the latest scan's hits while it is recent, and stops while one is
within the safety distance.  Goals it could never reach (a declared obstacle
on the straight way) are refused at once.  Teleport and reset cancel the goal
(the simulator asks, with reason "teleported" / "reset").  It publishes
``turtle1/cmd_vel`` only while a goal runs, and refuses to start while another
navigator serves ``navigate_to``.
"""

from __future__ import annotations

import math
import time

import numpy as np

from messages import (
    Ack,
    Cancel,
    GoalState,
    LaserScan,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    TurtleStatus,
    Twist,
)
from messages.angles import degrees_0_360, heading_degrees, heading_radians
from messages.keys import CANCEL, CLIENT_TOKEN_PREFIX, CMD_VEL, FEEDBACK, NAVIGATE_TO, OBSTACLES, POSE, STATUS
from nodes.control import Phase, Pose2D, Tolerances, choose_direction, control_step, remaining_time
from nodes.goal import allowed_speed, goal_problem, heading_error_deg, path_problem
from nodes.params import NavigatorParams
from nodes.scan import circles_corridor_clearance, corridor_clearance, hit_points, off_walls
from runtime import Node, Request, run_main

WATCHDOG_PERIOD = 0.05  # s


class Goal:
    def __init__(self, request: Request[NavigateToRequest]):
        self.request = request
        body = request.body
        self.x, self.y = body.x, body.y
        self.theta_deg = degrees_0_360(body.theta)  # reduced in degrees, exactly, before anything else
        self.theta = heading_radians(self.theta_deg)
        self.target = Pose2D(self.x, self.y, self.theta)
        self.client = f"{CLIENT_TOKEN_PREFIX}/{body.client}" if body.client else ""
        self.start = time.monotonic()
        self.phase = Phase.POSITION
        self.direction = 0  # chosen with the first pose
        self.state = GoalState.TURNING
        self.blocked_since: float | None = None


class Navigator:
    def __init__(self, node: Node[NavigatorParams]):
        self.node = node
        self.pose: Pose | None = None
        self.pose_time = 0.0
        self.battery: float | None = None
        self.scan_points = np.zeros((0, 2))  # world coordinates of the latest scan's hits, walls left out
        self.scan_time = -math.inf
        self.scans_stale = True  # as said last in the log
        self.goal: Goal | None = None
        node.claim("srv", NAVIGATE_TO, "serves navigate_to and drives the turtle")
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
        node.on_shutdown(lambda: self.finish(False, "navigator shut down", "the navigator was stopped"))

    # -- inputs -------------------------------------------------------------
    def on_goal(self, request: Request[NavigateToRequest]) -> None:
        body = request.body
        p = self.node.params
        problem, detail = goal_problem(body, self.node.world), ""
        if problem is None and self.pose is not None:
            problem = path_problem(self.pose.x, self.pose.y, body.x, body.y, self.node.world, 0.5 * p.corridor_width)
        if problem is None and self.battery is not None and self.battery < p.min_battery:
            problem = "battery low"
            detail = (
                f"battery at {self.battery:.1f} %, below the navigator's min_battery {p.min_battery:g} %: "
                "`turtlectl reset` recharges it"
            )
        if problem is not None:
            self.node.log.info(
                "refused goal (%g, %g, %.1f deg): %s", body.x, body.y, degrees_0_360(body.theta), problem
            )
            where = {}
            if self.pose is not None:
                where = {"x": self.pose.x, "y": self.pose.y, "theta": heading_degrees(self.pose.theta)}
            request.respond(
                NavigateToResponse(success=False, time_taken=0.0, reason=problem, refused=True, detail=detail, **where)
            )
            return
        self.finish(False, "preempted", "a new goal replaced it")
        self.goal = Goal(request)
        self.node.log.info("goal (%.3f, %.3f, %.1f deg)", body.x, body.y, self.goal.theta_deg)
        if not self.scans_fresh():
            self.node.log.warning("no recent scan: avoiding only the declared obstacles of the world")
        self.drive()

    def on_cancel(self, request: Request[Cancel]) -> None:
        if self.goal is None:
            request.respond(Ack(ok=False, detail="no goal is running"))
            return
        goal = self.goal
        reason = request.body.reason or "canceled"
        self.finish(False, reason, "" if reason == "canceled" else f"the turtle was {reason} while it drove")
        request.respond(Ack(detail=f"canceled the goal ({goal.x:g}, {goal.y:g}, {goal.theta_deg:g} deg)"))

    def on_client(self, key: str, alive: bool) -> None:
        if not alive and self.goal is not None and key == self.goal.client:
            self.finish(False, "caller gone", "its caller went away: Ctrl-C, killed, or its own --timeout")

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
            self.finish(False, "timeout", f"not there after the navigator's goal_timeout of {p.goal_timeout:g} s")
        elif now - max(self.pose_time, goal.start) > p.pose_timeout:
            self.finish(False, "no pose", f"no {POSE} for {p.pose_timeout:g} s: is the simulator running?")
        stale = not self.scans_fresh()
        if stale != self.scans_stale:
            self.scans_stale = stale
            if stale:
                self.node.log.warning("scans stopped: avoiding only the declared obstacles of the world")
            else:
                self.node.log.info("scans are back")

    def scans_fresh(self) -> bool:
        return time.monotonic() - self.scan_time <= self.node.params.scan_timeout

    def feedback(self) -> None:
        goal, pose = self.goal, self.pose
        if goal is None or pose is None:
            return
        limits = self.node.limits
        eta = remaining_time(pose, goal.target, goal.direction or 1, limits)
        progress = self.feedback_pub.publish(  # for observers; the same, stamped, to the caller
            NavigateToFeedback(
                state=goal.state,
                distance_remaining=math.hypot(goal.x - pose.x, goal.y - pose.y),
                heading_remaining=heading_error_deg(goal.theta, pose.theta),
                eta=eta,
                elapsed=time.monotonic() - goal.start,
                x=pose.x,
                y=pose.y,
                theta=heading_degrees(pose.theta),
                goal_x=goal.x,
                goal_y=goal.y,
                goal_theta=goal.theta_deg,
                scan_stale=not self.scans_fresh(),
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
            goal.direction = choose_direction(pose, goal.target, limits)
        cmd = control_step(
            pose,
            goal.target,
            phase=goal.phase,
            direction=goal.direction,
            limits=limits,
            gains=p.gains,
            tolerances=Tolerances(position=p.position_tolerance, heading=math.radians(p.heading_tolerance)),
        )
        goal.phase = cmd.phase
        if cmd.phase is Phase.DONE:
            self.finish(True, "")
            return
        linear = cmd.linear
        if linear != 0.0:
            allowed, what = self.obstacle_speed(pose, linear, math.hypot(goal.x - pose.x, goal.y - pose.y))
            linear = math.copysign(min(abs(linear), allowed), linear)
            if allowed == 0.0:
                self.blocked(goal, cmd.angular, what)
                return
        if goal.blocked_since is not None:
            goal.blocked_since = None
            self.node.log.info("way clear: resuming")
        goal.state = GoalState.DRIVING if linear != 0.0 else GoalState.TURNING
        self.cmd_pub.publish(Twist(linear=linear, angular=cmd.angular))

    def blocked(self, goal: Goal, angular: float, what: str) -> None:
        """Something is too close in the direction of travel: do not drive, but keep turning
        (towards the goal, which may well lead away from it)."""
        now = time.monotonic()
        p = self.node.params
        if goal.blocked_since is None:
            goal.blocked_since = now
            self.node.log.info("%s within %.2f m in the direction of travel: stopped", what, p.safety_distance)
        goal.state = GoalState.BLOCKED
        self.cmd_pub.publish(Twist(linear=0.0, angular=angular))
        if now - goal.blocked_since > p.blocked_timeout:
            self.finish(
                False,
                "blocked",
                f"{what} stayed within the safety distance ({p.safety_distance:g} m) ahead for the "
                f"navigator's blocked_timeout of {p.blocked_timeout:g} s",
            )

    def obstacle_speed(self, pose: Pose, linear: float, distance_to_goal: float) -> tuple[float, str]:
        """Fastest speed (m/s) allowed for travel in the direction of ``linear``, and what
        limits it: the declared obstacles always, the latest scan's hits while it is recent;
        0 while one between the turtle and its goal, inside the corridor along its path, is
        within the safety distance."""
        p = self.node.params
        half_width = 0.5 * p.corridor_width
        heading = pose.theta if linear > 0 else pose.theta + math.pi
        nearest, obstacle = circles_corridor_clearance(self.node.world.obstacles, pose.x, pose.y, heading, half_width)
        what = f"the obstacle at ({obstacle.x:g}, {obstacle.y:g})" if obstacle is not None else ""
        if self.scans_fresh():
            seen = corridor_clearance(self.scan_points, pose.x, pose.y, heading, half_width)
            if seen < nearest:
                nearest, what = seen, "something the scan sees"
        return allowed_speed(nearest, distance_to_goal, p.safety_distance, p.obstacle_decel), what

    def finish(self, success: bool, reason: str, detail: str = "") -> None:
        """End the running goal (if any): stop the turtle and answer its caller."""
        goal, self.goal = self.goal, None
        if goal is None:
            return
        self.cmd_pub.publish(Twist())
        pose = self.pose
        final = {}
        if pose is not None:
            final = {
                "position_error": math.hypot(goal.x - pose.x, goal.y - pose.y),
                "heading_error": heading_error_deg(goal.theta, pose.theta),
                "x": pose.x,
                "y": pose.y,
                "theta": heading_degrees(pose.theta),
            }
        response = NavigateToResponse(
            success=success, time_taken=time.monotonic() - goal.start, reason=reason, detail=detail, **final
        )
        level = self.node.log.info if success else self.node.log.warning
        level(
            "goal %s in %.3f s (error %.4f m, %.2f deg)%s",
            "reached" if success else "failed",
            response.time_taken,
            response.position_error,
            response.heading_error,
            (f": {reason}" if reason else "") + (f" ({detail})" if detail else ""),
        )
        goal.request.respond(response)


def main() -> None:
    run_main(Navigator, NavigatorParams)


if __name__ == "__main__":
    main()
