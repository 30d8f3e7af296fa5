"""The local planner and driver of one goal: pure, the clock passed in.

It drives the turtle to ``target`` along a path (nodes.planner) round what it knows of its
surroundings (nodes.surroundings).  A goal walled in by what the scan sees waits
("replanning") and gives up after ``blocked_timeout`` unless a way opens.  When something
seen comes onto the path, or the turtle strays from it, the path is planned again.  On
each pose the control law (nodes.control) gives a velocity: along the path (follow_step),
then to the goal itself on its final straight run (control_step); the driver slows it for
obstacles in the direction of travel, and stops driving (it only turns, and plans again)
while one is within the safety distance.  Once the law is within the tolerances, or the
turtle would come to rest within them if stopped now, it is stopped; it has arrived when it
is at rest within them with nothing but a stop on its way (a turtle answered while still turning
could brake past its heading).

Two events: ``step`` (a pose) returns a ``Step``, what to do: ``Drive`` (send this command),
``Arrived`` or ``Blocked`` (give up: blocked or no way for blocked_timeout); ``scanned``
(after the surroundings took in a scan) plans again if what it saw is in the way.  Each
gives the lines to log with it (``Note``).  The goal's lifecycle (who asked, timeouts,
feedback, the answer) is nodes.goal_machine's; this knows only where to go and how.

Units: m, s; rad.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from turtlectl.messages import GoalState, Pose, Twist
from turtlectl.messages.angles import wrap_radians
from turtlectl.messages.world import Limits
from turtlectl.nodes.control import (
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
from turtlectl.nodes.goal import allowed_speed
from turtlectl.nodes.params import NavigatorParams
from turtlectl.nodes.planner import Path, Segment, Track
from turtlectl.nodes.scan import path_clearance
from turtlectl.nodes.surroundings import Surroundings

#: m: a turtle this far from its path has its path planned again from where it is
OFF_PATH = 0.3

#: m/s and rad/s: a turtle this slow is at rest (a goal is reached only at rest within the
#: tolerances: braking from a turn can carry one 2 deg past its heading)
REST_LINEAR = 1e-3
REST_ANGULAR = 1e-3


@dataclass(frozen=True)
class Note:
    """A line for the node's log, at ``level`` (logging.INFO, logging.WARNING)."""

    level: int
    text: str


@dataclass(frozen=True)
class Drive:
    """Send ``twist`` (a stop while it waits, turning only while blocked) and go on."""

    twist: Twist
    notes: tuple[Note, ...] = ()


@dataclass(frozen=True)
class Arrived:
    """At rest within the tolerances, and the last command a stop: the goal is reached."""

    notes: tuple[Note, ...] = ()


@dataclass(frozen=True)
class Blocked:
    """Blocked, or no way, for ``blocked_timeout``: give up; ``detail`` says why, ``twist``
    is the command given on the way (a stop, or turning in place)."""

    twist: Twist
    detail: str
    notes: tuple[Note, ...] = ()


#: what a pose asks of the goal's lifecycle
Step = Drive | Arrived | Blocked


class Driver:
    """Drives to ``target`` (rad): its path and where the turtle is on it, and how it goes."""

    def __init__(self, target: Pose2D, around: Surroundings, params: NavigatorParams, limits: Limits):
        self.target = target
        self.around = around
        self.limits = limits
        self.set_params(params)
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
        self.last_command_was_stop = True  # the last command given was a stop (none yet: taken as one)
        self._notes: list[Note] = []

    def set_params(self, params: NavigatorParams) -> None:
        """Use ``params`` from the next step: tolerances, gains, safety and blocked_timeout."""
        self.params = params
        self.tolerances = Tolerances(position=params.position_tolerance, heading=math.radians(params.heading_tolerance))

    # -- events -------------------------------------------------------------
    def step(self, pose: Pose, now: float) -> Step:
        """The turtle is at ``pose``: what to do now."""
        self._notes = []
        replanned = False
        while True:
            if self.path is None and (self.blocked_since is None or not self.around.scans_fresh(now)):
                # the first plan; while there is no way, each scan plans again (scanned()), not each
                # pose, unless scans have stopped (then only the declared obstacles remain: the way may open)
                self._replan(pose, now, "")
            if self.path is None:  # no way round what the scan sees: wait
                return self._no_way(now)
            if self.track is None:
                break
            cmd, self.progress, self.off_path = follow_step(
                pose, self.track, self.progress, limits=self.limits, gains=self.params.gains
            )
            if self.off_path > OFF_PATH and not replanned:  # once: a new path starts where the turtle is
                self._replan(pose, now, f"{self.off_path:.2f} m off the path")
                replanned = True
                continue
            if self.track.s[self.progress] >= self.track.final_start - 0.01:
                self.track = None  # the final straight run: to the goal itself
            break
        if self.track is None:
            cmd = self._law(pose)
            # close in the law may change the direction (back up, never turn round): it holds from
            # then on, so an overshoot beyond `near` is backed out of, not turned round for
            self.phase, self.direction = cmd.phase, cmd.direction
            if self.last_command_was_stop and at_rest(pose) and self._within_tolerances(pose):
                # at rest, and no command but a stop on its way to the simulator: it stays here
                return Arrived(self._said())
            if cmd.phase is Phase.DONE or self._stops_inside(pose):
                # within the tolerances, or would come to rest within them if stopped now: it is
                # where it rests that counts, so stop, and answer from the pose at rest
                self.state = GoalState.TURNING
                return Drive(self._command(Twist()), self._said())
            to_go = math.hypot(self.target.x - pose.x, self.target.y - pose.y)
        else:
            to_go = self.track.length - float(self.track.s[self.progress]) + self.off_path
        linear = cmd.linear
        if linear != 0.0:
            allowed, what = self._obstacle_speed(pose, linear, to_go, now)
            linear = math.copysign(min(abs(linear), allowed), linear)
            if allowed == 0.0:
                return self._blocked(pose, cmd.angular, what, now)
        if self.blocked_since is not None:
            self.blocked_since = None
            self._note(logging.INFO, "way clear: resuming")
        self.state = GoalState.DRIVING if linear != 0.0 else GoalState.TURNING
        return Drive(self._command(Twist(linear=linear, angular=cmd.angular)), self._said())

    def scanned(self, pose: Pose, now: float) -> tuple[Note, ...]:
        """The surroundings took in a scan, the turtle at ``pose``: plan again if what it saw
        came onto the path (or if there was no way, or the turtle is blocked)."""
        self._notes = []
        if self.path is None or self.state is GoalState.BLOCKED:
            self._replan(pose, now, "")
        else:
            seen = self.around.seen(now)
            if self.track is not None:
                in_way = self.track.blocked_by(seen, self.progress)
            else:  # on the final straight run
                target = self.target
                in_way = Track(Path((Segment(pose.x, pose.y, target.x, target.y),))).blocked_by(seen)
            if in_way is not None:
                self._replan(pose, now, f"something the scan sees at ({in_way.x:.2f}, {in_way.y:.2f}) is in the way")
        return self._said()

    # -- queries ------------------------------------------------------------
    def remaining(self, pose: Pose) -> tuple[float, float]:
        """How far (m) the turtle at ``pose`` still has to go, and in how long (s), about."""
        target, track = self.target, self.track
        if track is not None:
            along = track.length - float(track.s[self.progress]) + self.off_path
            end = self.path.pieces[-1] if self.path is not None else None
            end_heading = end.heading(end.length) if end is not None else pose.theta
            return along, path_remaining_time(along, end_heading, target, self.limits)
        along = math.hypot(target.x - pose.x, target.y - pose.y)
        return along, remaining_time(pose, target, self.direction or 1, self.limits)

    # -- inside -------------------------------------------------------------
    def _replan(self, pose: Pose, now: float, why: str) -> None:
        """Plan the path from ``pose`` (``why``: the reason to log, empty for the first plan
        and for tries while there is no way)."""
        first = self.path is None and self.replans == 0 and self.blocked_since is None
        seen = self.around.seen(now) if self.around.scans_fresh(now) else []
        path = self.around.plan(pose, self.target.x, self.target.y, seen)
        if path is None:
            if self.path is not None or self.blocked_since is None:
                self._note(logging.WARNING, "no way round what the scan sees: waiting, planning again with each scan")
            self.path, self.track, self.outline = None, None, []
            self.state = GoalState.REPLANNING
            if self.blocked_since is None:
                self.blocked_since = now
            return
        if not first:
            self.replans += 1
        if why or self.path is None and not first:
            self._note(logging.INFO, f"planned again ({why or 'a way is open'}): {path.length:.2f} m to go")
        self.path, self.outline, self.progress = path, path.outline(), 0
        self.track = None if path.direct else Track(path)
        self.phase = Phase.POSITION
        if path.direct and self.direction == 0:
            self.direction = choose_direction(pose, self.target, self.limits)
        elif not path.direct:
            self.direction = 1

    def _no_way(self, now: float) -> Step:
        """No way round what the scan sees: stand still and wait, until blocked_timeout."""
        twist = self._command(Twist())
        target, keep = self.target, self.around.keep
        fresh = self.around.scans_fresh(now)
        gap, near = self.around.costmap.nearest(target.x, target.y) if fresh else (math.inf, None)
        why = (
            f"something the scan sees lay within {keep:g} m of the goal (seen at "
            f"({near[0]:.2f}, {near[1]:.2f}), {gap:.2f} m from it)"
            if near is not None and gap < keep
            else "there was no way round what the scan sees"
        )
        return self._until_timeout(twist, now, why)

    def _blocked(self, pose: Pose, angular: float, what: str, now: float) -> Step:
        """Something is too close in the direction of travel: do not drive, but keep turning
        (towards the path, which may well lead away from it); look for another way at once."""
        p = self.params
        if self.blocked_since is None:
            self.blocked_since = now
            self._note(logging.INFO, f"{what} within {p.safety_distance:.2f} m in the direction of travel: stopped")
            self._replan(pose, now, f"{what} is in the way")
        if self.path is None:  # no way: _replan said so, and waits
            twist = self._command(Twist())
        else:
            self.state = GoalState.BLOCKED
            twist = self._command(Twist(linear=0.0, angular=angular))
        return self._until_timeout(
            twist, now, f"{what} stayed within the safety distance ({p.safety_distance:g} m) ahead"
        )

    def _until_timeout(self, twist: Twist, now: float, what: str) -> Step:
        """``twist``, or give up if blocked (or no way) for longer than blocked_timeout."""
        p = self.params
        if self.blocked_since is not None and now - self.blocked_since > p.blocked_timeout:
            detail = f"{what} for the navigator's blocked_timeout of {p.blocked_timeout:g} s"
            return Blocked(twist, detail, self._said())
        return Drive(twist, self._said())

    def _command(self, twist: Twist) -> Twist:
        """``twist``, remembering whether it was a stop."""
        self.last_command_was_stop = twist.linear == 0.0 and twist.angular == 0.0
        return twist

    def _within_tolerances(self, pose: Pose) -> bool:
        """Whether ``pose``, on the final turn, is within the caller's tolerances of the goal
        (the law aims at half of each, DONE: a turtle at rest between the two has arrived all the same)."""
        target = self.target
        return (
            self.phase in (Phase.HEADING, Phase.DONE)
            and math.hypot(target.x - pose.x, target.y - pose.y) <= self.tolerances.position
            and abs(wrap_radians(target.theta - pose.theta)) <= self.tolerances.heading
        )

    def _stops_inside(self, pose: Pose) -> bool:
        """Whether the turtle, told to stop now, comes to rest where the law is done: so that
        it need not creep the last of the way at the law's slowing speeds and then wait to stop."""
        if self.phase is not Phase.HEADING:
            return False
        rest = resting_pose(pose, pose.linear_velocity, pose.angular_velocity, self.limits)
        return self._law(rest).phase is Phase.DONE

    def _law(self, pose: Pose | Pose2D) -> Command:
        """The control law's step from ``pose`` to the goal itself (its final straight run)."""
        return control_step(
            pose,
            self.target,
            phase=self.phase,
            direction=self.direction or 1,
            limits=self.limits,
            gains=self.params.gains,
            tolerances=self.tolerances,
        )

    def _obstacle_speed(self, pose: Pose, linear: float, to_go: float, now: float) -> tuple[float, str]:
        """Fastest speed (m/s) allowed, and what limits it.  Along the path: what still brakes
        in time (at obstacle_decel) before where it comes within half the corridor width of
        something, 0 within the safety distance of that.  Straight ahead (the direction of
        ``linear``, which is where the turtle goes while it turns onto its path): 0 if
        driving the safety distance that way would bring it nearer something than half the
        corridor width.  The declared obstacles count always (the path keeps clear of them:
        this is a safety net), the latest scan's hits that the world does not explain while
        that scan is recent, and the other turtles (nodes.traffic: where they are, and where
        one it gives way to is about to be)."""
        p, obstacles = self.params, self.around.world.obstacles
        half_width = 0.5 * p.corridor_width
        points = self.around.unknown_points if self.around.scans_fresh(now) else np.zeros((0, 2))
        others = self.around.traffic.points(now)
        if len(others):
            points = np.vstack([points.reshape(-1, 2), others])
        look = min(to_go, self.limits.max_linear_speed**2 / (2.0 * p.obstacle_decel) + p.safety_distance + 0.1)
        track = self.track
        if track is not None:
            end = int(np.searchsorted(track.s, track.s[self.progress] + look)) + 1
            ahead, along = track.xy[self.progress : end], track.s[self.progress : end] - track.s[self.progress]
        else:  # the final straight run
            heading = math.atan2(self.target.y - pose.y, self.target.x - pose.x)
            ahead, along = _line(pose.x, pose.y, heading, look)
        nearest, obstacle = path_clearance(ahead, along, points, obstacles, pose.x, pose.y, half_width)
        heading = pose.theta if linear > 0 else pose.theta + math.pi
        straight, along = _line(pose.x, pose.y, heading, min(to_go, p.safety_distance))
        close, close_obstacle = path_clearance(straight, along, points, obstacles, pose.x, pose.y, half_width)
        if math.isfinite(close):
            nearest, obstacle = 0.0, close_obstacle
        what = (
            f"the obstacle at ({obstacle.x:g}, {obstacle.y:g})" if obstacle is not None else "something the scan sees"
        )
        return allowed_speed(nearest, to_go, p.safety_distance, p.obstacle_decel), what

    def _note(self, level: int, text: str) -> None:
        self._notes.append(Note(level, text))

    def _said(self) -> tuple[Note, ...]:
        notes, self._notes = tuple(self._notes), []
        return notes


def _line(x: float, y: float, heading: float, length: float, spacing: float = 0.02) -> tuple[np.ndarray, np.ndarray]:
    """Points (m) every ``spacing`` m or less from (x, y) along ``heading`` (rad) for
    ``length`` m, and each one's distance from (x, y)."""
    along = np.linspace(0.0, length, max(2, math.ceil(length / spacing) + 1))
    return np.column_stack((x + along * math.cos(heading), y + along * math.sin(heading))), along


def at_rest(pose: Pose) -> bool:
    """Whether ``pose`` shows the turtle (nearly) still: both its speeds below REST_*."""
    return abs(pose.linear_velocity) <= REST_LINEAR and abs(pose.angular_velocity) <= REST_ANGULAR
