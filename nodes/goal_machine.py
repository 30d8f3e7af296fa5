"""The navigator's goal lifecycle as a state machine: pure, the clock passed in.

A goal's lifecycle, as Nav2's NavigateToPose:

* accepted (or refused at once: invalid, unreachable past a declared obstacle, battery
  low), then fed back to its caller (``feedback``), and ended by one NavigateToResponse:
  reached (the turtle at rest within the tolerances: once the law is within them the
  machine stops the turtle and answers with the pose it comes to rest in), or not with a
  reason;
* a new goal preempts the running one ("preempted"); a cancel ends it ("canceled", or the
  reason the canceller gives: the simulator sends "teleported" and "reset"); a caller whose
  liveliness token vanishes has its goal canceled ("caller gone"); no pose for
  ``pose_timeout`` ends it ("no pose"), as do ``goal_timeout`` ("timeout") and
  ``blocked_timeout`` blocked ("blocked"); a navigator that stops ends it
  ("navigator shut down").

A goal is driven along a path (nodes.planner): the shortest way round the declared
obstacles and what the scans have seen that the world does not declare (nodes.costmap:
remembered where it was seen, forgotten when beams pass through where it was; used while
the latest scan is recent, ``scan_timeout``), each kept ``robot_radius + clearance`` away.  A goal no path
reaches round the declared obstacles is refused; one walled in by what the scan sees
waits ("replanning") and ends "blocked" after ``blocked_timeout`` unless a way opens.
When something seen comes onto the path, or the turtle strays from it, the path is
planned again.  On each pose the control law (nodes.control) gives a velocity: along the
path (follow_step), then to the goal itself on its final straight run (control_step); the
machine slows it for obstacles in the direction of travel, and stops driving (it only
turns, and plans again) while one is within the safety distance.

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
from messages.angles import degrees_0_360, heading_degrees, heading_difference_degrees, heading_radians, wrap_radians
from messages.keys import CLIENT_TOKEN_PREFIX, POSE
from messages.world import Limits, World
from nodes.control import (
    Command,
    Phase,
    Pose2D,
    Tolerances,
    choose_direction,
    control_step,
    follow_step,
    path_remaining_time,
    remaining_time,
    resting_pose,
)
from nodes.costmap import HIT_PAD, Costmap
from nodes.goal import allowed_speed, goal_problem, no_way
from nodes.params import NavigatorParams
from nodes.planner import Circle, Path, Segment, Track, containing, escape, inflate, shortest_path, wall_plugs
from nodes.scan import hit_points, off_walls, path_clearance, unexplained

#: m: a turtle this far from its path has its path planned again from where it is
OFF_PATH = 0.3

#: m/s and rad/s: a turtle this slow is at rest (a goal is reached only at rest within the
#: tolerances: braking from a turn carried one 2 deg past its heading, issue 22)
REST_LINEAR = 1e-3
REST_ANGULAR = 1e-3

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
        self.blocked_since: float | None = None  # blocked, or no way: since when
        self.path: Path | None = None  # None: not planned yet, or no way round what the scan sees
        self.outline: list[tuple[float, float]] = []  # the path, drawn (feedback)
        self.track: Track | None = None  # the path to follow before the final straight run (None: on it)
        self.progress = 0  # index of the turtle's place on the track
        self.off_path = 0.0  # m from the track, at the last step
        self.replans = 0
        self.stopping = True  # the last command given for it was a stop (none yet: taken as one)


#: the detail of a goal canceled with a reason of its own
CANCEL_DETAILS = {"canceled": "", "teleop": "the keyboard took over (turtlectl teleop)"}


class GoalMachine(Generic[C]):
    """One navigator's goals, one at a time.  ``goal`` is the running one (None: idle)."""

    def __init__(self, params: NavigatorParams, world: World, limits: Limits):
        self.world = world
        self.limits = limits
        self.set_params(params)
        self.costmap = Costmap(world.size)  # what the scans have seen that the world does not declare
        self.unknown: list[Circle] = []  # the costmap's circles after the latest scan
        self.goal: Goal[C] | None = None
        self.latest_pose: Pose | None = None
        self.pose_time = 0.0
        self.battery: float | None = None
        self.scan_points = np.zeros((0, 2))  # world coordinates of the latest scan's hits, walls left out
        self.unknown_points = np.zeros((0, 2))  # those of them the declared obstacles do not explain
        self.scan_time = -math.inf
        self.scans_stale: bool | None = None  # as said last in the log; None: no scan yet, nothing said
        self._out: list[Action] = []

    def set_params(self, params: NavigatorParams) -> None:
        """Use ``params`` from now on (also at run time, ``turtlectl param set``): tolerances
        and timeouts apply at the next step, a new robot_radius or clearance at the next plan
        (a running goal's path is planned again with the next scan)."""
        self.params = params
        self.tolerances = Tolerances(position=params.position_tolerance, heading=math.radians(params.heading_tolerance))
        self.keep = params.robot_radius + params.clearance  # m the turtle keeps from every obstacle
        self.declared = inflate(self.world.obstacles, self.keep)

    # -- events -------------------------------------------------------------
    def start(self, request: NavigateToRequest, caller: C, now: float) -> list[Action]:
        """A new goal from ``caller``: refused at once, or run (preempting the running one)."""
        p = self.params
        problem, detail = None, goal_problem(request, self.world, self.keep)
        if detail is not None:
            problem = "invalid goal"
        here = self.latest_pose
        if problem is None and here is not None and self._plan(here, request.x, request.y, []) is None:
            problem = "unreachable"
            detail = no_way(here.x, here.y, request.x, request.y, self.keep, self._walled_in(here, request))
        if problem is None and self.battery is not None and self.battery < p.min_battery:
            problem = "battery low"
            detail = (
                f"battery at {self.battery:.1f} %, below the navigator's min_battery {p.min_battery:g} %: "
                "`turtlectl reset` recharges it"
            )
        if problem is not None:
            theta = degrees_0_360(request.theta)
            self._note(
                logging.INFO, f"refused goal ({request.x:g}, {request.y:g}, {theta:.1f} deg): {problem}: {detail}"
            )
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
        detail = CANCEL_DETAILS.get(reason, f"the turtle was {reason} while it drove")  # teleported, reset
        self._finish(now, False, reason, detail)
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

    def scan(self, scan: LaserScan, now: float) -> list[Action]:
        """A scan: its hits (walls left out) are what the turtle avoids until ``scan_timeout``
        after ``now``; what the world does not declare among them goes into the costmap,
        whose beams also clear what is no longer there, and the costmap is planned round.  The
        running goal's path is planned again if that comes onto it (or if there was no way,
        or the turtle is blocked).  A scan that does not say where it was taken is placed at
        the latest pose (ignored without one)."""
        origin = (scan.origin_x, scan.origin_y, scan.origin_theta)
        if not all(math.isfinite(v) for v in origin):
            here = self.latest_pose
            if here is None:
                return []
            origin = (here.x, here.y, here.theta)
        angles = scan.angle_min + scan.angle_increment * np.arange(len(scan.ranges))
        points = hit_points(*origin, np.asarray(scan.ranges, dtype=float), angles)
        self.scan_points = off_walls(points, self.world.size)
        self.unknown_points = unexplained(self.scan_points, self.world.obstacles)
        ranges = np.asarray(scan.ranges, dtype=float)
        self.costmap.update(*origin, ranges, scan.angle_min, scan.angle_increment, scan.range_max, self.unknown_points)
        self.unknown = self.costmap.circles()
        self.scan_time = now
        goal = self.goal
        if goal is not None and self.latest_pose is not None:
            if goal.path is None or goal.state is GoalState.BLOCKED:
                self._replan(goal, now, "")
            else:
                seen = self._seen()
                track = goal.track
                if track is not None:
                    in_way = track.blocked_by(seen, goal.progress)
                else:  # on the final straight run
                    pose, target = self.latest_pose, goal.target
                    in_way = Track(Path((Segment(pose.x, pose.y, target.x, target.y),))).blocked_by(seen)
                if in_way is not None:
                    self._replan(
                        goal, now, f"something the scan sees at ({in_way.x:.2f}, {in_way.y:.2f}) is in the way"
                    )
        return self._flush()

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
        track = goal.track
        if track is not None:
            along = track.length - float(track.s[goal.progress]) + goal.off_path
            end = goal.path.pieces[-1] if goal.path is not None else None
            end_heading = end.heading(end.length) if end is not None else pose.theta
            eta = path_remaining_time(along, end_heading, target, self.limits)
        else:
            along = math.hypot(target.x - pose.x, target.y - pose.y)
            eta = remaining_time(pose, target, goal.direction or 1, self.limits)
        return goal.caller, NavigateToFeedback(
            state=goal.state,
            distance_remaining=along,
            heading_remaining=heading_difference_degrees(target.theta, pose.theta),
            eta=eta,
            elapsed=now - goal.start,
            x=pose.x,
            y=pose.y,
            theta=heading_degrees(pose.theta),
            goal_x=target.x,
            goal_y=target.y,
            goal_theta=goal.theta_deg,
            scan_stale=not self.scans_fresh(now),
            path=goal.outline,
            replans=goal.replans,
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
    def _seen(self) -> list[Circle]:
        """What the scans have seen that the world does not declare, grown by what the turtle keeps."""
        return [Circle(c.x, c.y, c.r + self.keep) for c in self.unknown]

    def _plan(self, pose: Pose, x: float, y: float, seen: list[Circle]) -> Path | None:
        """The shortest way from ``pose`` to (x, y) round the declared obstacles and ``seen``,
        through no gap between one of them and a wall too narrow for the turtle (unless the
        goal lies in it)."""
        seen = [part for c in seen for part in self._split_on(x, y, c)]
        circles = self.declared + seen
        plugs = wall_plugs(circles, self.world.size, self.params.robot_radius)
        circles += [c for c in plugs if containing(x, y, [c]) is None]
        return shortest_path((pose.x, pose.y), (x, y), escape(pose.x, pose.y, circles), self.world.size)

    def _split_on(self, x: float, y: float, seen: Circle) -> list[Circle]:
        """``seen`` (one of ``_seen()``), or if (x, y) lies in it, one circle for each hit it
        covers: a circle covers its hits with room to spare (up to half a costmap square), which
        must not put a goal beyond the margin of everything seen inside the margin.  So a goal
        is walled in by what is seen exactly when a hit lies within ``keep`` of it."""
        if containing(x, y, [seen]) is None:
            return [seen]
        parts = []
        for hx, hy in self.costmap.within(seen.x, seen.y, seen.r - self.keep):
            r, d = HIT_PAD + self.keep, math.hypot(x - hx, y - hy)
            # a goal at least ``keep`` from a hit is outside its circle: the pad is not the margin
            parts.append(Circle(float(hx), float(hy), r if d < self.keep else min(r, d - 1e-6)))
        return parts

    def _walled_in(self, pose: Pose, request: NavigateToRequest) -> str:
        """Which of the turtle and the goal the declared obstacles enclose, when no way joins
        them: the one that reaches fewer of the world's free corners (a pocket at a corner
        holds one; "the goal" if they reach as many)."""
        s = self.world.size
        corners = [
            (x, y) for x, y in ((0.0, 0.0), (s, 0.0), (0.0, s), (s, s)) if containing(x, y, self.declared) is None
        ]

        def reached(x: float, y: float) -> int:
            circles = escape(x, y, self.declared)
            return sum(shortest_path((x, y), c, circles, s) is not None for c in corners)

        return "the turtle" if reached(pose.x, pose.y) < reached(request.x, request.y) else "the goal"

    def _replan(self, goal: Goal[C], now: float, why: str) -> None:
        """Plan the goal's path from where the turtle is (``why``: the reason to log, empty
        for the first plan and for tries while there is no way)."""
        pose = self.latest_pose
        if pose is None:
            return
        first = goal.path is None and goal.replans == 0 and goal.blocked_since is None
        seen = self._seen() if self.scans_fresh(now) else []
        path = self._plan(pose, goal.target.x, goal.target.y, seen)
        if path is None:
            if goal.path is not None or goal.blocked_since is None:
                self._note(logging.WARNING, "no way round what the scan sees: waiting, planning again with each scan")
            goal.path, goal.track, goal.outline = None, None, []
            goal.state = GoalState.REPLANNING
            if goal.blocked_since is None:
                goal.blocked_since = now
            return
        if not first:
            goal.replans += 1
        if why or goal.path is None and not first:
            self._note(logging.INFO, f"planned again ({why or 'a way is open'}): {path.length:.2f} m to go")
        goal.path, goal.outline, goal.progress = path, path.outline(), 0
        goal.track = None if path.direct else Track(path)
        goal.phase = Phase.POSITION
        if path.direct and goal.direction == 0:
            goal.direction = choose_direction(pose, goal.target, self.limits)
        elif not path.direct:
            goal.direction = 1

    def _drive(self, now: float) -> None:
        goal, pose = self.goal, self.latest_pose
        if goal is None or pose is None:
            return
        if goal.path is None and (goal.blocked_since is None or not self.scans_fresh(now)):
            # the first plan; while there is no way, each scan plans again (scan()), not each pose,
            # unless scans have stopped (then only the declared obstacles remain: the way may open)
            self._replan(goal, now, "")
        if goal.path is None:  # no way round what the scan sees: wait
            self._command(goal, Twist())
            target = goal.target
            gap, near = self.costmap.nearest(target.x, target.y) if self.scans_fresh(now) else (math.inf, None)
            why = (
                f"something the scan sees lay within {self.keep:g} m of the goal (seen at "
                f"({near[0]:.2f}, {near[1]:.2f}), {gap:.2f} m from it)"
                if near is not None and gap < self.keep
                else "there was no way round what the scan sees"
            )
            self._check_blocked_timeout(goal, now, why)
            return
        if goal.track is not None:
            cmd, goal.progress, goal.off_path = follow_step(
                pose, goal.track, goal.progress, limits=self.limits, gains=self.params.gains
            )
            if goal.off_path > OFF_PATH:
                self._replan(goal, now, f"{goal.off_path:.2f} m off the path")
                self._drive(now)
                return
            if goal.track.s[goal.progress] >= goal.track.final_start - 0.01:
                goal.track = None  # the final straight run: to the goal itself
        if goal.track is None:
            cmd = self._law(goal, pose)
            goal.phase = cmd.phase
            if goal.stopping and at_rest(pose) and (cmd.phase is Phase.DONE or self._within_tolerances(goal, pose)):
                # at rest, and no command but a stop on its way to the simulator: it stays here
                self._finish(now, True, "")
                return
            if cmd.phase is Phase.DONE or self._stops_inside(goal, pose):
                # within the tolerances, or would come to rest within them if stopped now: it is
                # where it rests that counts, so stop, and answer from the pose at rest
                goal.state = GoalState.TURNING
                self._command(goal, Twist())
                return
            to_go = math.hypot(goal.target.x - pose.x, goal.target.y - pose.y)
        else:
            to_go = goal.track.length - float(goal.track.s[goal.progress]) + goal.off_path
        linear = cmd.linear
        if linear != 0.0:
            allowed, what = self._obstacle_speed(goal, pose, linear, to_go, now)
            linear = math.copysign(min(abs(linear), allowed), linear)
            if allowed == 0.0:
                self._blocked(goal, cmd.angular, what, now)
                return
        if goal.blocked_since is not None:
            goal.blocked_since = None
            self._note(logging.INFO, "way clear: resuming")
        goal.state = GoalState.DRIVING if linear != 0.0 else GoalState.TURNING
        self._command(goal, Twist(linear=linear, angular=cmd.angular))

    def _command(self, goal: Goal[C], twist: Twist) -> None:
        """Send ``twist`` for ``goal``, remembering whether it was a stop."""
        goal.stopping = twist.linear == 0.0 and twist.angular == 0.0
        self._out.append(twist)

    def _within_tolerances(self, goal: Goal[C], pose: Pose) -> bool:
        """Whether ``pose`` is within the caller's tolerances of the goal (the law aims at half
        of each: a turtle at rest between the two has arrived all the same)."""
        target = goal.target
        return (
            goal.phase is Phase.HEADING
            and math.hypot(target.x - pose.x, target.y - pose.y) <= self.tolerances.position
            and abs(wrap_radians(target.theta - pose.theta)) <= self.tolerances.heading
        )

    def _stops_inside(self, goal: Goal[C], pose: Pose) -> bool:
        """Whether the turtle, told to stop now, comes to rest where the law is done: so that
        it need not creep the last of the way at the law's slowing speeds and then wait to stop."""
        if goal.phase is not Phase.HEADING:
            return False
        rest = resting_pose(pose, pose.linear_velocity, pose.angular_velocity, self.limits)
        return self._law(goal, rest).phase is Phase.DONE

    def _law(self, goal: Goal[C], pose: Pose | Pose2D) -> Command:
        """The control law's step from ``pose`` to the goal itself (its final straight run)."""
        return control_step(
            pose,
            goal.target,
            phase=goal.phase,
            direction=goal.direction or 1,
            limits=self.limits,
            gains=self.params.gains,
            tolerances=self.tolerances,
        )

    def _blocked(self, goal: Goal[C], angular: float, what: str, now: float) -> None:
        """Something is too close in the direction of travel: do not drive, but keep turning
        (towards the path, which may well lead away from it); look for another way at once."""
        p = self.params
        if goal.blocked_since is None:
            goal.blocked_since = now
            self._note(logging.INFO, f"{what} within {p.safety_distance:.2f} m in the direction of travel: stopped")
            self._replan(goal, now, f"{what} is in the way")
        if goal.path is None:  # no way: _replan said so, and waits
            self._command(goal, Twist())
        else:
            goal.state = GoalState.BLOCKED
            self._command(goal, Twist(linear=0.0, angular=angular))
        self._check_blocked_timeout(
            goal, now, f"{what} stayed within the safety distance ({p.safety_distance:g} m) ahead"
        )

    def _check_blocked_timeout(self, goal: Goal[C], now: float, what: str) -> None:
        p = self.params
        if goal.blocked_since is not None and now - goal.blocked_since > p.blocked_timeout:
            self._finish(
                now, False, "blocked", f"{what} for the navigator's blocked_timeout of {p.blocked_timeout:g} s"
            )

    def _obstacle_speed(self, goal: Goal[C], pose: Pose, linear: float, to_go: float, now: float) -> tuple[float, str]:
        """Fastest speed (m/s) allowed, and what limits it.  Along the path: what still brakes
        in time (at obstacle_decel) before where it comes within half the corridor width of
        something, 0 within the safety distance of that.  Straight ahead (the direction of
        ``linear``, which is where the turtle goes while it turns onto its path): 0 if
        driving the safety distance that way would bring it nearer something than half the
        corridor width.  The declared obstacles count always (the path keeps clear of them:
        this is a safety net), the latest scan's hits that the world does not explain while
        that scan is recent."""
        p = self.params
        half_width = 0.5 * p.corridor_width
        points = self.unknown_points if self.scans_fresh(now) else np.zeros((0, 2))
        look = min(to_go, self.limits.max_linear_speed**2 / (2.0 * p.obstacle_decel) + p.safety_distance + 0.1)
        track = goal.track
        if track is not None:
            end = int(np.searchsorted(track.s, track.s[goal.progress] + look)) + 1
            ahead, along = track.xy[goal.progress : end], track.s[goal.progress : end] - track.s[goal.progress]
        else:  # the final straight run
            ahead, along = _line(pose.x, pose.y, math.atan2(goal.target.y - pose.y, goal.target.x - pose.x), look)
        nearest, obstacle = path_clearance(ahead, along, points, self.world.obstacles, pose.x, pose.y, half_width)
        heading = pose.theta if linear > 0 else pose.theta + math.pi
        straight, along = _line(pose.x, pose.y, heading, min(to_go, p.safety_distance))
        close, close_obstacle = path_clearance(
            straight, along, points, self.world.obstacles, pose.x, pose.y, half_width
        )
        if math.isfinite(close):
            nearest, obstacle = 0.0, close_obstacle
        what = (
            f"the obstacle at ({obstacle.x:g}, {obstacle.y:g})" if obstacle is not None else "something the scan sees"
        )
        return allowed_speed(nearest, to_go, p.safety_distance, p.obstacle_decel), what

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


def _line(x: float, y: float, heading: float, length: float, spacing: float = 0.02) -> tuple[np.ndarray, np.ndarray]:
    """Points (m) every ``spacing`` m or less from (x, y) along ``heading`` (rad) for
    ``length`` m, and each one's distance from (x, y)."""
    along = np.linspace(0.0, length, max(2, math.ceil(length / spacing) + 1))
    return np.column_stack((x + along * math.cos(heading), y + along * math.sin(heading))), along


def at_rest(pose: Pose) -> bool:
    """Whether ``pose`` shows the turtle (nearly) still: both its speeds below REST_*."""
    return abs(pose.linear_velocity) <= REST_LINEAR and abs(pose.angular_velocity) <= REST_ANGULAR
