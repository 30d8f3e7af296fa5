"""The navigator's control law as pure functions: no I/O, no clock, no zenoh.

A goal is reached in two phases: its POSITION, then its HEADING, turning in
place.  At the start of a goal the law picks the direction of
travel (forwards or backwards) that needs the least turning in all, and it
turns while driving: the speed fades with the heading error and is zero beyond
``drive_cone``.  Speeds follow a "brake in time" profile,
v = min(v_max, sqrt(2 a d), k d) (corrected for the simulator's 16 ms steps),
planned with the robot's acceleration limits so that the turtle brakes to rest
on the goal without overshoot or oscillation.

Units: m, rad, m/s, rad/s, m/s^2, rad/s^2, s.
"""

from __future__ import annotations

import enum
import math
from typing import Protocol

import msgspec

from turtlectl.messages.units import Positive
from turtlectl.messages.world import Limits
from turtlectl.nodes.planner import Path, Track
from turtlectl.sim.kinematics import STEP, wrap_angle

#: m: how far inside an arc of the path the follower may cut
SAG = 0.02


class Phase(enum.Enum):
    """Which part of the goal the law works on: its POSITION first, then its HEADING
    (turning in place); DONE once both are within the tolerances.  Not what the turtle is
    seen doing (turning, driving, blocked: messages.GoalState): the law turns while it
    works on the position, too."""

    POSITION = "position"
    HEADING = "heading"
    DONE = "done"


class Planar(Protocol):
    """Anything with a planar pose: x, y (m) and theta (rad), such as a Pose message,
    the simulator's TurtleState or a Pose2D."""

    @property
    def x(self) -> float: ...

    @property
    def y(self) -> float: ...

    @property
    def theta(self) -> float: ...


class Pose2D(msgspec.Struct, frozen=True):
    """A planar pose: x, y in m, theta in rad (a goal, as the law pursues it)."""

    x: float
    y: float
    theta: float


class Tolerances(msgspec.Struct, frozen=True, kw_only=True):
    """What the caller calls success: within ``position`` m of the goal position and
    ``heading`` rad of its heading.  The law aims at half of each."""

    position: float
    heading: float


class Gains(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """Tuning of the control law (units in the field comments)."""

    k_linear: Positive = 30.0  # 1/s: speed per metre of distance near the goal
    k_angular: Positive = 40.0  # 1/s: turn rate per radian of heading error near the target
    brake_fraction: Positive = 1.0  # fraction: of the acceleration limits, used to plan braking
    drive_cone: Positive = math.radians(120.0)  # rad: beyond this heading error, turn before driving
    near: Positive = 0.05  # m: within this of the goal, drive whichever way is shorter
    lookahead: Positive = 0.5  # m: on a path round obstacles, steer for the point this far ahead on it


class Command(msgspec.Struct, kw_only=True):
    """Output of one control step: velocities (m/s, rad/s), the phase after it, and
    the direction of travel (+1 forwards, -1 backwards)."""

    linear: float
    angular: float
    phase: Phase
    direction: int = 1


def profile(error: float, v_max: float, decel: float, k: float, dt: float = STEP) -> float:
    """Speed magnitude that brakes to rest exactly at ``error`` (>= 0) away.

    The braking curve is the one of a system that changes speed by ``decel * dt``
    per step of ``dt`` s (the simulator's Euler steps): v^2/(2a) + v dt/2 = d;
    dt = 0 gives the continuous v = sqrt(2 a d).
    """
    half = 0.5 * decel * dt
    return min(v_max, math.sqrt(half * half + 2.0 * decel * error) - half, k * error)


def trapezoid_time(distance: float, v_max: float, accel: float) -> float:
    """Shortest time (s) to cover ``distance`` from rest to rest within v_max and accel."""
    distance = abs(distance)
    if distance * accel <= v_max * v_max:  # never reaches v_max: triangle
        return 2.0 * math.sqrt(distance / accel)
    return distance / v_max + v_max / accel


def rotate_drive_rotate_time(start: Planar, goal: Planar, limits: Limits) -> float:
    """Time (s) of the naive plan under ``limits``: turn to face the goal, drive straight,
    turn to the final heading, each from rest to rest with a trapezoidal speed profile."""
    distance = math.hypot(goal.x - start.x, goal.y - start.y)
    w, a = limits.max_angular_speed, limits.max_angular_accel
    if distance == 0.0:
        return trapezoid_time(wrap_angle(goal.theta - start.theta), w, a)
    bearing = math.atan2(goal.y - start.y, goal.x - start.x)
    return (
        trapezoid_time(wrap_angle(bearing - start.theta), w, a)
        + trapezoid_time(distance, limits.max_linear_speed, limits.max_linear_accel)
        + trapezoid_time(wrap_angle(goal.theta - bearing), w, a)
    )


def choose_direction(pose: Planar, goal: Planar, limits: Limits) -> int:
    """+1 to drive forwards, -1 backwards: whichever needs less time turning in all."""
    bearing = math.atan2(goal.y - pose.y, goal.x - pose.x)

    def turning(facing: float) -> float:
        w, a = limits.max_angular_speed, limits.max_angular_accel
        return trapezoid_time(wrap_angle(facing - pose.theta), w, a) + trapezoid_time(
            wrap_angle(goal.theta - facing), w, a
        )

    return 1 if turning(bearing) <= turning(bearing + math.pi) else -1


def resting_pose(
    pose: Planar, linear: float, angular: float, limits: Limits, *, lag: int = 0, dt: float = STEP
) -> Pose2D:
    """Where a turtle at ``pose`` moving at (``linear`` m/s, ``angular`` rad/s) comes to rest
    if told to stop now (m, m, rad), as the simulator moves it in steps of ``dt`` s: ``lag``
    more steps at the speeds it has (0: the stop reaches the simulator before its next step,
    as it does while the navigator answers each pose in time), then braking at the
    acceleration limits, each speed covering (v - a dt) dt, (v - 2 a dt) dt, ... till still."""

    def travel(v: float, a: float) -> float:
        speed, drop = abs(v), a * dt
        n = math.floor(speed / drop)  # braking steps that still move it
        return math.copysign(lag * speed * dt + n * speed * dt - drop * dt * n * (n + 1) / 2.0, v)

    theta = wrap_angle(pose.theta + travel(angular, limits.max_angular_accel))
    d = travel(linear, limits.max_linear_accel)
    return Pose2D(pose.x + d * math.cos(pose.theta), pose.y + d * math.sin(pose.theta), theta)


def control_step(
    pose: Planar,
    goal: Planar,
    *,
    phase: Phase,
    direction: int,
    limits: Limits,
    gains: Gains,
    tolerances: Tolerances,
) -> Command:
    """One step of the control law from the current ``pose`` to ``goal`` (m, m, rad).

    ``phase`` is the one the last step returned (POSITION to begin with); ``direction``
    the one chosen for the goal (choose_direction).  The law aims at half of each of
    ``tolerances`` so that it finishes well inside them.  Returns DONE with zero speeds
    once both hold.
    """
    dx, dy = goal.x - pose.x, goal.y - pose.y
    distance = math.hypot(dx, dy)
    if phase is Phase.DONE:
        phase = Phase.HEADING
    if phase is Phase.HEADING and distance > tolerances.position:
        phase = Phase.POSITION
    if phase is Phase.POSITION and distance <= 0.5 * tolerances.position:
        phase = Phase.HEADING

    a_lin = gains.brake_fraction * limits.max_linear_accel
    a_ang = gains.brake_fraction * limits.max_angular_accel
    if phase is Phase.POSITION:
        alpha = wrap_angle(math.atan2(dy, dx) - pose.theta)
        if distance < gains.near:  # close in: never turn around, back up or creep on
            direction = 1 if abs(alpha) <= math.pi / 2 else -1
        if direction < 0:
            alpha = wrap_angle(alpha + math.pi)
        angular = math.copysign(profile(abs(alpha), limits.max_angular_speed, a_ang, gains.k_angular), alpha)
        speed = 0.0
        if abs(alpha) < gains.drive_cone:
            speed = profile(distance, limits.max_linear_speed, a_lin, gains.k_linear)
            speed *= max(0.0, math.cos(alpha)) * (1.0 - abs(alpha) / gains.drive_cone)
        return Command(linear=direction * speed, angular=angular, phase=phase, direction=direction)

    error = wrap_angle(goal.theta - pose.theta)
    if abs(error) <= 0.5 * tolerances.heading:
        return Command(linear=0.0, angular=0.0, phase=Phase.DONE, direction=direction)
    angular = math.copysign(profile(abs(error), limits.max_angular_speed, a_ang, gains.k_angular), error)
    return Command(linear=0.0, angular=angular, phase=Phase.HEADING, direction=direction)


def follow_step(
    pose: Planar, track: Track, progress: int, *, limits: Limits, gains: Gains
) -> tuple[Command, int, float]:
    """One step along ``track`` (a path round obstacles) before its final straight run:
    steer for the point ``gains.lookahead`` m ahead of the turtle's place on the path (less
    round tight arcs, so as to cut at most SAG m inside them), turning
    while driving as control_step does, at the speed that brakes to rest at the path's end.

    ``progress`` is the index the last step returned (0 to begin with).  Returns the command
    (phase POSITION, forwards), the new progress, and how far (m) the turtle is from the path.
    The caller hands over to control_step for the goal itself once the turtle reaches
    ``track.final_start``.
    """
    progress = track.project(pose.x, pose.y, progress)
    px, py = track.xy[progress]
    off = math.hypot(pose.x - px, pose.y - py)
    s = float(track.s[progress])
    # round a tight arc, steer for a nearer point: a chord of L across an arc of radius R
    # cuts L^2 / (8 R) inside it, kept to SAG
    lookahead = min(gains.lookahead, math.sqrt(8.0 * SAG * track.tightest(progress, s + gains.lookahead)))
    cx, cy = track.point_at(s + lookahead)
    alpha = wrap_angle(math.atan2(cy - pose.y, cx - pose.x) - pose.theta)
    a_lin = gains.brake_fraction * limits.max_linear_accel
    a_ang = gains.brake_fraction * limits.max_angular_accel
    angular = math.copysign(profile(abs(alpha), limits.max_angular_speed, a_ang, gains.k_angular), alpha)
    speed = 0.0
    if abs(alpha) < gains.drive_cone:
        speed = profile(track.length - s + off, limits.max_linear_speed, a_lin, gains.k_linear)
        speed *= max(0.0, math.cos(alpha)) * (1.0 - abs(alpha) / gains.drive_cone)
    return Command(linear=speed, angular=angular, phase=Phase.POSITION, direction=1), progress, off


def path_time(start_theta: float, path: Path, goal_theta: float, limits: Limits) -> float:
    """Time (s) of a careful driver on ``path`` under ``limits``: rotate–drive–rotate
    generalised to a path.  It turns in place to face the path, drives each run between
    corners from rest to rest (trapezoidal), turns in place at each corner, and turns to
    ``goal_theta`` at the end (rad).  Arcs are driven as they come (the pieces of a planned
    path meet without corners, so its runs are the whole path)."""
    w, a = limits.max_angular_speed, limits.max_angular_accel
    v, acc = limits.max_linear_speed, limits.max_linear_accel
    pieces = [p for p in path.pieces if p.length > 0.0]
    if not pieces:
        return trapezoid_time(wrap_angle(goal_theta - start_theta), w, a)
    total = trapezoid_time(wrap_angle(pieces[0].heading(0.0) - start_theta), w, a)
    run = 0.0
    for piece, after in zip(pieces, pieces[1:] + [None], strict=True):
        run += piece.length
        end_heading = piece.heading(piece.length)
        corner = wrap_angle((after.heading(0.0) if after is not None else goal_theta) - end_heading)
        if after is None or abs(corner) > 1e-6:
            total += trapezoid_time(run, v, acc) + trapezoid_time(corner, w, a)
            run = 0.0
    return total


def remaining_time(pose: Planar, goal: Planar, direction: int, limits: Limits) -> float:
    """Estimated s to finish from ``pose``: drive the remaining distance (travelling
    ``direction``), then turn to the final heading, each trapezoidal."""
    distance = math.hypot(goal.x - pose.x, goal.y - pose.y)
    facing = (
        pose.theta
        if distance < 1e-3
        else math.atan2(goal.y - pose.y, goal.x - pose.x) + (0.0 if direction > 0 else math.pi)
    )
    w, a = limits.max_angular_speed, limits.max_angular_accel
    return (
        trapezoid_time(wrap_angle(facing - pose.theta), w, a)
        + trapezoid_time(distance, limits.max_linear_speed, limits.max_linear_accel)
        + trapezoid_time(wrap_angle(goal.theta - facing), w, a)
    )


def path_remaining_time(remaining: float, end_heading: float, goal: Planar, limits: Limits) -> float:
    """Estimated s to finish ``remaining`` m of a path (from rest, trapezoidal) whose last
    piece heads ``end_heading`` rad, then turn to the goal's heading."""
    w, a = limits.max_angular_speed, limits.max_angular_accel
    return trapezoid_time(remaining, limits.max_linear_speed, limits.max_linear_accel) + trapezoid_time(
        wrap_angle(goal.theta - end_heading), w, a
    )
