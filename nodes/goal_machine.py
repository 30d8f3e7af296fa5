"""The navigator's goal lifecycle as a state machine: pure, the clock passed in.

A goal's lifecycle, as Nav2's NavigateToPose:

* accepted (or refused at once: invalid, unreachable past a declared obstacle, battery
  low), then fed back to its caller (``feedback``), and ended by one NavigateToResponse:
  reached (the turtle at rest within the tolerances: once the law is within them the
  driver stops the turtle and the goal is answered with the pose it comes to rest in), or
  not with a reason;
* no pose for ``pose_timeout`` ends it ("no pose"), as does ``blocked_timeout`` blocked
  ("blocked", the driver's say);
* the goal server (runtime.goals) ends it for the rest, and this machine says the answer
  (``end``): a newer goal ("preempted"), a cancel ("canceled", or the reason the canceller
  gives, with its own words for people; the navigator's own "teleported" and "reset" when the
  simulator is about to move the turtle), its caller gone
  ("caller gone"), ``goal_timeout`` ("timeout"), the navigator stopping ("navigator shut
  down").

How a goal is driven is not this module's: each running goal has a ``Driver``
(nodes.driver: the path, following it, the final run with the control law, slowing and
stopping for obstacles, arriving at rest), which plans with what the navigator knows of the
turtle's surroundings (nodes.surroundings: the declared obstacles, the scans, the costmap).
This machine hands it each pose and scan, carries out what it says (a command, arrived,
blocked), and keeps the rest: who asked, since when, the timeouts, the feedback, the answer.

Events are methods, each with ``now`` (s, any monotonic clock) where time matters:
``refusal`` (whether a goal is refused, before it touches the running one), ``start``,
``end``, ``pose``, ``scan``, ``status``, ``tick`` (the watchdog: no pose, scan staleness)
and ``feedback``.  Each returns what
the shell must do, in order: a ``Twist`` to publish on ``cmd_vel``, a ``Reply`` to a
goal's caller, a ``Note`` to log.  No I/O, no clock, no zenoh: the navigator process
(nodes.navigator) is the wiring, and tests script histories with a fake clock.

Units: m, s; degrees where people read them (requests, responses, feedback), rad inside.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

import numpy as np

from turtlectl.messages import (
    GoalState,
    LaserScan,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    Turtles,
    TurtleStatus,
    Twist,
)
from turtlectl.messages.angles import degrees_0_360, heading_degrees, heading_difference_degrees, heading_radians
from turtlectl.messages.keys import FIRST_TURTLE, POSE
from turtlectl.messages.world import Limits, World
from turtlectl.nodes.control import Pose2D
from turtlectl.nodes.driver import Arrived, Blocked, Driver, Note
from turtlectl.nodes.goal import goal_problem, no_way
from turtlectl.nodes.params import NavigatorParams
from turtlectl.nodes.surroundings import Surroundings
from turtlectl.runtime.goal_reasons import CALLER_GONE, CANCELED, INVALID_GOAL, PREEMPTED, SHUT_DOWN, TIMEOUT

__all__ = ["Action", "Goal", "GoalMachine", "Note", "Reply"]

C = TypeVar("C")  # the shell's handle on a goal's caller (a runtime.Request); opaque here


@dataclass(frozen=True)
class Reply(Generic[C]):
    """Answer ``to``, a goal's caller, with ``response``: this ends its call."""

    to: C
    response: NavigateToResponse


#: what an event asks the shell to do, in order
Action = Twist | Reply | Note


class Goal(Generic[C]):
    """The running goal: where to (``target``, rad), who asked, since when; ``driver`` drives it."""

    def __init__(self, request: NavigateToRequest, caller: C, now: float, driver: Callable[[Pose2D], Driver]):
        self.caller = caller
        self.theta_deg = degrees_0_360(request.theta)  # reduced in degrees, exactly, before anything else
        self.target = Pose2D(request.x, request.y, heading_radians(self.theta_deg))
        self.start = now
        self.driver = driver(self.target)

    @property
    def state(self) -> GoalState:
        """What the turtle is seen doing (the driver's say)."""
        return self.driver.state


#: the reason and detail of a goal the goal server ends, by the server's reason (runtime.goals);
#: another reason is a canceller's own (teleop's "teleop"; the navigator's "teleported", "reset"),
#: told with the canceller's own detail
ENDINGS = {
    PREEMPTED: (PREEMPTED, "a new goal replaced it"),
    CANCELED: (CANCELED, ""),
    CALLER_GONE: (CALLER_GONE, "its caller went away: Ctrl-C, killed, or its own --timeout"),
    SHUT_DOWN: ("navigator shut down", "the navigator was stopped"),
}


class GoalMachine(Generic[C]):
    """One navigator's goals, one at a time.  ``goal`` is the running one (None: idle)."""

    def __init__(
        self, params: NavigatorParams, world: World, limits: Limits, turtle: str = FIRST_TURTLE, pose_key: str = POSE
    ):
        self.world = world
        self.pose_key = pose_key  # the key its poses come on, as the node resolved it: what "no pose" names
        self.limits = limits
        self.surroundings = Surroundings(params, world, turtle)  # ``turtle``: the one it drives
        self.goal: Goal[C] | None = None
        self.set_params(params)
        self.latest_pose: Pose | None = None
        self.pose_time = 0.0
        self.battery: float | None = None
        self.scans_stale: bool | None = None  # as said last in the log; None: no scan yet, nothing said
        self._out: list[Action] = []

    def set_params(self, params: NavigatorParams) -> None:
        """Use ``params`` from now on (also at run time, ``turtlectl param set``): tolerances
        and timeouts apply at the next step, a new robot_radius or clearance at the next plan
        (a running goal's path is planned again with the next scan)."""
        self.params = params
        self.surroundings.set_params(params)
        if self.goal is not None:
            self.goal.driver.set_params(params)

    # -- events -------------------------------------------------------------
    def refusal(self, request: NavigateToRequest) -> tuple[NavigateToResponse, Note] | None:
        """Whether ``request`` is refused at once (invalid, unreachable, battery low): the
        answer and the line to log; None: it may run.  The running goal is not touched."""
        p, around = self.params, self.surroundings
        problem, detail = None, goal_problem(request, self.world, around.keep)
        if detail is not None:
            problem = INVALID_GOAL
        here = self.latest_pose
        if problem is None and here is not None and around.plan(here, request.x, request.y, []) is None:
            problem = "unreachable"
            walled = around.walled_in(here, request.x, request.y)
            detail = no_way(here.x, here.y, request.x, request.y, around.keep, walled)
        if problem is None and self.battery is not None and self.battery < p.min_battery:
            problem = "battery low"
            detail = (
                f"battery at {self.battery:.1f} %, below the navigator's min_battery {p.min_battery:g} %: "
                "`turtlectl reset` recharges it"
            )
        if problem is None:
            return None
        theta = degrees_0_360(request.theta)
        note = Note(logging.INFO, f"refused goal ({request.x:g}, {request.y:g}, {theta:.1f} deg): {problem}: {detail}")
        where = {}
        if here is not None:
            where = {"x": here.x, "y": here.y, "theta": heading_degrees(here.theta)}
        return NavigateToResponse(
            success=False, time_taken=0.0, reason=problem, refused=True, detail=detail, **where
        ), note

    def start(self, request: NavigateToRequest, caller: C, now: float) -> list[Action]:
        """A goal from ``caller``, accepted (``refusal`` said None): driven from now on.  The
        goal server has ended the one that ran (preemption is its: ``end``)."""
        if self.goal is not None:
            raise RuntimeError("a goal is running: the goal server ends it first (end)")
        goal = self.goal = Goal(
            request, caller, now, lambda target: Driver(target, self.surroundings, self.params, self.limits)
        )
        self._note(logging.INFO, f"goal ({request.x:.3f}, {request.y:.3f}, {goal.theta_deg:.1f} deg)")
        if not self.scans_fresh(now):
            self._note(logging.WARNING, "no recent scan: avoiding only the declared obstacles of the world")
        self._step(now)
        return self._flush()

    def end(self, reason: str, now: float, detail: str = "") -> list[Action]:
        """The goal server ends the running goal with ``reason`` (runtime.goals: "preempted",
        "canceled", "caller gone", "timeout", "shut down", or a canceller's own, with its
        ``detail`` for people if it gave one): stop the turtle, then its answer."""
        goal = self.goal
        if goal is None:
            return []
        if reason == TIMEOUT:
            why, told = TIMEOUT, f"not there after the navigator's goal_timeout of {self.params.goal_timeout:g} s"
        else:
            why, told = ENDINGS.get(reason, (reason, f"the turtle was {reason} while it drove"))
        self._finish(now, False, why, detail or told)
        return self._flush()

    def pose(self, pose: Pose, now: float) -> list[Action]:
        """The turtle's pose: the control step for the running goal."""
        self.latest_pose, self.pose_time = pose, now
        self._step(now)
        return self._flush()

    def pose_heard(self, now: float) -> None:
        """A pose arrived at ``now`` whose control step is still to come (the navigator's
        thread is behind, on a loaded machine): the simulator is not silent, so no "no pose"."""
        self.pose_time = max(self.pose_time, now)

    def status(self, status: TurtleStatus) -> None:
        """The robot's status: its battery decides whether goals are accepted."""
        self.battery = status.battery

    def scan(self, scan: LaserScan, now: float) -> list[Action]:
        """A scan, taken into the surroundings (nodes.surroundings: placed at the latest pose
        if it does not say where it was taken; ignored without one); the running goal's
        driver plans again if what it saw comes onto the path."""
        here = self.latest_pose
        if not self.surroundings.scan(scan, here, now):
            return []
        if self.goal is not None and here is not None:
            self._out += self.goal.driver.scanned(here, now)
        return self._flush()

    def tick(self, now: float) -> list[Action]:
        """The watchdog, while a goal runs: pose_timeout, and saying when scans stop (and come
        back).  goal_timeout is the goal server's deadline (runtime.goals)."""
        goal = self.goal
        if goal is None:
            return []
        p = self.params
        if now - max(self.pose_time, goal.start) > p.pose_timeout:
            self._finish(
                now, False, "no pose", f"no {self.pose_key} for {p.pose_timeout:g} s: is the simulator running?"
            )
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

    def feedback(self, now: float) -> NavigateToFeedback | None:
        """Progress of the running goal; None while idle or without a pose."""
        goal, pose = self.goal, self.latest_pose
        if goal is None or pose is None:
            return None
        target, driver = goal.target, goal.driver
        along, eta = driver.remaining(pose)
        return NavigateToFeedback(
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
            path=driver.outline,
            replans=driver.replans,
        )

    # -- queries ------------------------------------------------------------
    def turtles(self, msg: Turtles, now: float) -> None:
        """Every turtle's pose (``turtles``): the others, in the way or about to be (nodes.traffic)."""
        self.surroundings.traffic.update(msg, now)

    def scans_fresh(self, now: float) -> bool:
        """The latest scan is recent enough (``scan_timeout``) to avoid what it saw."""
        return self.surroundings.scans_fresh(now)

    @property
    def scan_points(self) -> np.ndarray:
        """World coordinates (m) of the latest scan's hits, walls left out."""
        return self.surroundings.scan_points

    @property
    def unknown_points(self) -> np.ndarray:
        """Those of the latest scan's hits that the declared obstacles do not explain."""
        return self.surroundings.unknown_points

    @property
    def scan_time(self) -> float:
        """When (s) the latest scan came (-inf: none yet)."""
        return self.surroundings.scan_time

    # -- inside -------------------------------------------------------------
    def _step(self, now: float) -> None:
        """Hand the running goal's driver the latest pose, and carry out what it says."""
        goal, pose = self.goal, self.latest_pose
        if goal is None or pose is None:
            return
        step = goal.driver.step(pose, now)
        self._out += step.notes
        if isinstance(step, Arrived):
            self._finish(now, True, "")
            return
        self._out.append(step.twist)
        if isinstance(step, Blocked):
            self._finish(now, False, "blocked", step.detail)

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
