"""The navigator's goal lifecycle as a state machine: pure, the clock passed in.

A goal's lifecycle, as Nav2's NavigateToPose:

* accepted (or refused at once: invalid, unreachable past a declared obstacle, battery
  low), then fed back to its caller (``feedback``), and ended by one NavigateToResponse:
  reached, or not with a reason;
* a new goal preempts the running one ("preempted"); a cancel ends it ("canceled", or the
  reason the canceller gives: the simulator sends "teleported" and "reset"); a caller whose
  liveliness token vanishes has its goal canceled ("caller gone"); no pose for
  ``pose_timeout`` ends it ("no pose"), as do ``goal_timeout`` ("timeout") and
  ``blocked_timeout`` blocked ("blocked"); a navigator that stops ends it
  ("navigator shut down").

On each pose the control law (nodes.control) gives a velocity; the machine slows it for
obstacles in the direction of travel, the world's declared ones always and the latest
scan's hits while that scan is recent (``scan_timeout``), and stops driving (it only
turns) while one is within the safety distance.

Events are methods, each with ``now`` (s, any monotonic clock) where time matters:
``start``, ``cancel``, ``caller_gone``, ``pose``, ``scan``, ``status``, ``tick`` (the
watchdog: timeouts and scan staleness), ``feedback`` and ``shutdown``.  Each returns what
the shell must do, in order: a ``Twist`` to publish on ``cmd_vel``, a ``Reply`` to a
goal's caller, a ``Note`` to log.  No I/O, no clock, no zenoh: the navigator process
(nodes.navigator) is the wiring, and tests script histories with a fake clock.

Units: m, s; degrees where people read them (requests, responses, feedback), rad inside.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Generic, TypeVar

import numpy as np

from messages import (
    Ack,
    GoalState,
    LaserScan,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    TurtleStatus,
    Twist,
)
from messages.angles import degrees_0_360, heading_degrees, heading_difference_degrees, heading_radians
from messages.keys import CLIENT_TOKEN_PREFIX, POSE
from messages.world import Limits, World
from nodes.control import Phase, Pose2D, Tolerances, choose_direction, control_step, remaining_time
from nodes.goal import allowed_speed, goal_problem, path_problem
from nodes.params import NavigatorParams
from nodes.scan import circles_corridor_clearance, corridor_clearance, hit_points, off_walls

C = TypeVar("C")  # the shell's handle on a goal's caller (a runtime.Request); opaque here


@dataclass(frozen=True)
class Reply(Generic[C]):
    """Answer ``to``, a goal's caller, with ``response``: this ends its call."""

    to: C
    response: NavigateToResponse


@dataclass(frozen=True)
class Note:
    """A line for the node's log, at ``level`` (logging.INFO, logging.WARNING)."""

    level: int
    text: str


#: what an event asks the shell to do, in order
Action = Twist | Reply | Note


class Goal(Generic[C]):
    """The running goal: where to (``target``, rad), who asked, since when, and how it goes."""

    def __init__(self, request: NavigateToRequest, caller: C, now: float):
        self.caller = caller
        self.theta_deg = degrees_0_360(request.theta)  # reduced in degrees, exactly, before anything else
        self.target = Pose2D(request.x, request.y, heading_radians(self.theta_deg))
        self.client = f"{CLIENT_TOKEN_PREFIX}/{request.client}" if request.client else ""
        self.start = now
        self.phase = Phase.POSITION  # what the control law works on
        self.direction = 0  # of travel, chosen with the first pose
        self.state = GoalState.TURNING  # what the turtle is seen doing
        self.blocked_since: float | None = None


class GoalMachine(Generic[C]):
    """One navigator's goals, one at a time.  ``goal`` is the running one (None: idle)."""

    def __init__(self, params: NavigatorParams, world: World, limits: Limits):
        self.params = params
        self.world = world
        self.limits = limits
        self.tolerances = Tolerances(position=params.position_tolerance, heading=math.radians(params.heading_tolerance))
        self.goal: Goal[C] | None = None
        self.latest_pose: Pose | None = None
        self.pose_time = 0.0
        self.battery: float | None = None
        self.scan_points = np.zeros((0, 2))  # world coordinates of the latest scan's hits, walls left out
        self.scan_time = -math.inf
        self.scans_stale: bool | None = None  # as said last in the log; None: no scan yet, nothing said
        self._out: list[Action] = []

    # -- events -------------------------------------------------------------
    def start(self, request: NavigateToRequest, caller: C, now: float) -> list[Action]:
        """A new goal from ``caller``: refused at once, or run (preempting the running one)."""
        p = self.params
        problem, detail = goal_problem(request, self.world), ""
        here = self.latest_pose
        if problem is None and here is not None:
            problem = path_problem(here.x, here.y, request.x, request.y, self.world, 0.5 * p.corridor_width)
        if problem is None and self.battery is not None and self.battery < p.min_battery:
            problem = "battery low"
            detail = (
                f"battery at {self.battery:.1f} %, below the navigator's min_battery {p.min_battery:g} %: "
                "`turtlectl reset` recharges it"
            )
        if problem is not None:
            theta = degrees_0_360(request.theta)
            self._note(logging.INFO, f"refused goal ({request.x:g}, {request.y:g}, {theta:.1f} deg): {problem}")
            where = {}
            if here is not None:
                where = {"x": here.x, "y": here.y, "theta": heading_degrees(here.theta)}
            response = NavigateToResponse(
                success=False, time_taken=0.0, reason=problem, refused=True, detail=detail, **where
            )
            self._out.append(Reply(caller, response))
            return self._flush()
        self._finish(now, False, "preempted", "a new goal replaced it")
        goal = self.goal = Goal(request, caller, now)
        self._note(logging.INFO, f"goal ({request.x:.3f}, {request.y:.3f}, {goal.theta_deg:.1f} deg)")
        if not self.scans_fresh(now):
            self._note(logging.WARNING, "no recent scan: avoiding only the declared obstacles of the world")
        self._drive(now)
        return self._flush()

    def cancel(self, reason: str, now: float) -> tuple[Ack, list[Action]]:
        """End the running goal with ``reason`` (empty: "canceled"); the Ack is for the canceller."""
        goal = self.goal
        if goal is None:
            return Ack(ok=False, detail="no goal is running"), []
        reason = reason or "canceled"
        self._finish(now, False, reason, "" if reason == "canceled" else f"the turtle was {reason} while it drove")
        target = goal.target
        return Ack(detail=f"canceled the goal ({target.x:g}, {target.y:g}, {goal.theta_deg:g} deg)"), self._flush()

    def caller_gone(self, key: str, now: float) -> list[Action]:
        """The liveliness token ``key`` vanished: if it is the running goal's caller's, end that goal."""
        if self.goal is not None and self.goal.client and key == self.goal.client:
            self._finish(now, False, "caller gone", "its caller went away: Ctrl-C, killed, or its own --timeout")
        return self._flush()

    def pose(self, pose: Pose, now: float) -> list[Action]:
        """The turtle's pose: the control step for the running goal."""
        self.latest_pose, self.pose_time = pose, now
        self._drive(now)
        return self._flush()

    def status(self, status: TurtleStatus) -> None:
        """The robot's status: its battery decides whether goals are accepted."""
        self.battery = status.battery

    def scan(self, scan: LaserScan, now: float) -> None:
        """A scan: its hits (walls left out) are what the turtle avoids until ``scan_timeout``
        after ``now``.  A scan that does not say where it was taken is placed at the latest
        pose (ignored without one)."""
        origin = (scan.origin_x, scan.origin_y, scan.origin_theta)
        if not all(math.isfinite(v) for v in origin):
            here = self.latest_pose
            if here is None:
                return
            origin = (here.x, here.y, here.theta)
        angles = scan.angle_min + scan.angle_increment * np.arange(len(scan.ranges))
        points = hit_points(*origin, np.asarray(scan.ranges, dtype=float), angles)
        self.scan_points = off_walls(points, self.world.size)
        self.scan_time = now

    def tick(self, now: float) -> list[Action]:
        """The watchdog, while a goal runs: goal_timeout, pose_timeout, and saying when scans
        stop (and come back)."""
        goal = self.goal
        if goal is None:
            return []
        p = self.params
        if now - goal.start > p.goal_timeout:
            self._finish(now, False, "timeout", f"not there after the navigator's goal_timeout of {p.goal_timeout:g} s")
        elif now - max(self.pose_time, goal.start) > p.pose_timeout:
            self._finish(now, False, "no pose", f"no {POSE} for {p.pose_timeout:g} s: is the simulator running?")
        stale = not self.scans_fresh(now)
        if self.scans_stale is None:  # before the first scan nothing has stopped; the first one is no news
            self.scans_stale = False if not stale else None
        elif stale != self.scans_stale:
            self.scans_stale = stale
            if stale:
                self._note(logging.WARNING, "scans stopped: avoiding only the declared obstacles of the world")
            else:
                self._note(logging.INFO, "scans are back")
        return self._flush()

    def feedback(self, now: float) -> tuple[C, NavigateToFeedback] | None:
        """Progress of the running goal and its caller; None while idle or without a pose."""
        goal, pose = self.goal, self.latest_pose
        if goal is None or pose is None:
            return None
        target = goal.target
        return goal.caller, NavigateToFeedback(
            state=goal.state,
            distance_remaining=math.hypot(target.x - pose.x, target.y - pose.y),
            heading_remaining=heading_difference_degrees(target.theta, pose.theta),
            eta=remaining_time(pose, target, goal.direction or 1, self.limits),
            elapsed=now - goal.start,
            x=pose.x,
            y=pose.y,
            theta=heading_degrees(pose.theta),
            goal_x=target.x,
            goal_y=target.y,
            goal_theta=goal.theta_deg,
            scan_stale=not self.scans_fresh(now),
        )

    def shutdown(self, now: float) -> list[Action]:
        """The navigator stops: end the running goal (the turtle is told to stop)."""
        self._finish(now, False, "navigator shut down", "the navigator was stopped")
        return self._flush()

    # -- queries ------------------------------------------------------------
    def scans_fresh(self, now: float) -> bool:
        """The latest scan is recent enough (``scan_timeout``) to avoid what it saw."""
        return now - self.scan_time <= self.params.scan_timeout

    # -- inside -------------------------------------------------------------
    def _drive(self, now: float) -> None:
        goal, pose = self.goal, self.latest_pose
        if goal is None or pose is None:
            return
        if goal.direction == 0:
            goal.direction = choose_direction(pose, goal.target, self.limits)
        cmd = control_step(
            pose,
            goal.target,
            phase=goal.phase,
            direction=goal.direction,
            limits=self.limits,
            gains=self.params.gains,
            tolerances=self.tolerances,
        )
        goal.phase = cmd.phase
        if cmd.phase is Phase.DONE:
            self._finish(now, True, "")
            return
        linear = cmd.linear
        if linear != 0.0:
            distance = math.hypot(goal.target.x - pose.x, goal.target.y - pose.y)
            allowed, what = self._obstacle_speed(pose, linear, distance, now)
            linear = math.copysign(min(abs(linear), allowed), linear)
            if allowed == 0.0:
                self._blocked(goal, cmd.angular, what, now)
                return
        if goal.blocked_since is not None:
            goal.blocked_since = None
            self._note(logging.INFO, "way clear: resuming")
        goal.state = GoalState.DRIVING if linear != 0.0 else GoalState.TURNING
        self._out.append(Twist(linear=linear, angular=cmd.angular))

    def _blocked(self, goal: Goal[C], angular: float, what: str, now: float) -> None:
        """Something is too close in the direction of travel: do not drive, but keep turning
        (towards the goal, which may well lead away from it)."""
        p = self.params
        if goal.blocked_since is None:
            goal.blocked_since = now
            self._note(logging.INFO, f"{what} within {p.safety_distance:.2f} m in the direction of travel: stopped")
        goal.state = GoalState.BLOCKED
        self._out.append(Twist(linear=0.0, angular=angular))
        if now - goal.blocked_since > p.blocked_timeout:
            self._finish(
                now,
                False,
                "blocked",
                f"{what} stayed within the safety distance ({p.safety_distance:g} m) ahead for the "
                f"navigator's blocked_timeout of {p.blocked_timeout:g} s",
            )

    def _obstacle_speed(self, pose: Pose, linear: float, distance_to_goal: float, now: float) -> tuple[float, str]:
        """Fastest speed (m/s) allowed for travel in the direction of ``linear``, and what
        limits it: the declared obstacles always, the latest scan's hits while it is recent;
        0 while one between the turtle and its goal, inside the corridor along its path, is
        within the safety distance."""
        p = self.params
        half_width = 0.5 * p.corridor_width
        heading = pose.theta if linear > 0 else pose.theta + math.pi
        nearest, obstacle = circles_corridor_clearance(self.world.obstacles, pose.x, pose.y, heading, half_width)
        what = f"the obstacle at ({obstacle.x:g}, {obstacle.y:g})" if obstacle is not None else ""
        if self.scans_fresh(now):
            seen = corridor_clearance(self.scan_points, pose.x, pose.y, heading, half_width)
            if seen < nearest:
                nearest, what = seen, "something the scan sees"
        return allowed_speed(nearest, distance_to_goal, p.safety_distance, p.obstacle_decel), what

    def _finish(self, now: float, success: bool, reason: str, detail: str = "") -> None:
        """End the running goal (if any): stop the turtle, then answer its caller."""
        goal, self.goal = self.goal, None
        if goal is None:
            return
        self._out.append(Twist())
        pose, target = self.latest_pose, goal.target
        final = {}
        if pose is not None:
            final = {
                "position_error": math.hypot(target.x - pose.x, target.y - pose.y),
                "heading_error": heading_difference_degrees(target.theta, pose.theta),
                "x": pose.x,
                "y": pose.y,
                "theta": heading_degrees(pose.theta),
            }
        response = NavigateToResponse(
            success=success, time_taken=now - goal.start, reason=reason, detail=detail, **final
        )
        why = (f": {reason}" if reason else "") + (f" ({detail})" if detail else "")
        self._note(
            logging.INFO if success else logging.WARNING,
            f"goal {'reached' if success else 'failed'} in {response.time_taken:.3f} s "
            f"(error {response.position_error:.4f} m, {response.heading_error:.2f} deg){why}",
        )
        self._out.append(Reply(goal.caller, response))

    def _note(self, level: int, text: str) -> None:
        self._out.append(Note(level, text))

    def _flush(self) -> list[Action]:
        out, self._out = self._out, []
        return out
