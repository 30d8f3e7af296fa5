"""The navigator's control law as pure functions: no I/O, no clock, no zenoh.

A goal is reached in two phases: DRIVE to the position, then ALIGN to the
final heading in place.  At the start of a goal the law picks the direction of
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

import msgspec

from messages.units import Positive
from messages.world import Limits
from sim.kinematics import STEP, wrap_angle


class Phase(enum.StrEnum):
    DRIVE = "driving"
    ALIGN = "aligning"
    DONE = "done"


class Gains(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """Tuning of the control law (units in the field comments)."""

    k_linear: Positive = 30.0  # 1/s: speed per metre of distance near the goal
    k_angular: Positive = 40.0  # 1/s: turn rate per radian of heading error near the target
    brake_fraction: Positive = 1.0  # of the acceleration limits, used to plan braking
    drive_cone: Positive = math.radians(120.0)  # rad: beyond this heading error, turn before driving
    near: Positive = 0.05  # m: within this of the goal, drive whichever way is shorter


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


def rotate_drive_rotate_time(
    x: float, y: float, theta: float, goal_x: float, goal_y: float, goal_theta: float, limits: Limits
) -> float:
    """Time (s) of the naive plan under ``limits``: turn to face the goal, drive straight,
    turn to the final heading, each from rest to rest with a trapezoidal speed profile."""
    distance = math.hypot(goal_x - x, goal_y - y)
    turn = trapezoid_time
    if distance == 0.0:
        return turn(wrap_angle(goal_theta - theta), limits.max_angular_speed, limits.max_angular_accel)
    bearing = math.atan2(goal_y - y, goal_x - x)
    return (
        turn(wrap_angle(bearing - theta), limits.max_angular_speed, limits.max_angular_accel)
        + trapezoid_time(distance, limits.max_linear_speed, limits.max_linear_accel)
        + turn(wrap_angle(goal_theta - bearing), limits.max_angular_speed, limits.max_angular_accel)
    )


def choose_direction(
    x: float, y: float, theta: float, goal_x: float, goal_y: float, goal_theta: float, limits: Limits
) -> int:
    """+1 to drive forwards, -1 backwards: whichever needs less time turning in all."""
    bearing = math.atan2(goal_y - y, goal_x - x)

    def turning(facing: float) -> float:
        w, a = limits.max_angular_speed, limits.max_angular_accel
        return trapezoid_time(wrap_angle(facing - theta), w, a) + trapezoid_time(wrap_angle(goal_theta - facing), w, a)

    return 1 if turning(bearing) <= turning(bearing + math.pi) else -1


def control_step(
    x: float,
    y: float,
    theta: float,
    goal_x: float,
    goal_y: float,
    goal_theta: float,
    phase: Phase,
    direction: int,
    limits: Limits,
    gains: Gains,
    position_tolerance: float,
    heading_tolerance: float,
) -> Command:
    """One step of the control law from the current pose (m, m, rad) to the goal (m, m, rad).

    ``direction`` is the one chosen for the goal (choose_direction).
    ``position_tolerance`` (m) and ``heading_tolerance`` (rad) are what the
    caller calls success; the law aims at half of each so that it finishes
    well inside them.  Returns DONE with zero speeds once both hold.
    """
    dx, dy = goal_x - x, goal_y - y
    distance = math.hypot(dx, dy)
    if phase is Phase.DONE:
        phase = Phase.ALIGN
    if phase is Phase.ALIGN and distance > position_tolerance:
        phase = Phase.DRIVE
    if phase is Phase.DRIVE and distance <= 0.5 * position_tolerance:
        phase = Phase.ALIGN

    a_lin = gains.brake_fraction * limits.max_linear_accel
    a_ang = gains.brake_fraction * limits.max_angular_accel
    if phase is Phase.DRIVE:
        alpha = wrap_angle(math.atan2(dy, dx) - theta)
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

    error = wrap_angle(goal_theta - theta)
    if abs(error) <= 0.5 * heading_tolerance:
        return Command(linear=0.0, angular=0.0, phase=Phase.DONE, direction=direction)
    angular = math.copysign(profile(abs(error), limits.max_angular_speed, a_ang, gains.k_angular), error)
    return Command(linear=0.0, angular=angular, phase=Phase.ALIGN, direction=direction)


def remaining_time(
    x: float, y: float, theta: float, goal_x: float, goal_y: float, goal_theta: float, direction: int, limits: Limits
) -> float:
    """Estimated s to finish from the current pose: drive the remaining distance
    (travelling ``direction``), then turn to the final heading, each trapezoidal."""
    distance = math.hypot(goal_x - x, goal_y - y)
    facing = theta if distance < 1e-3 else math.atan2(goal_y - y, goal_x - x) + (0.0 if direction > 0 else math.pi)
    w, a = limits.max_angular_speed, limits.max_angular_accel
    return (
        trapezoid_time(wrap_angle(facing - theta), w, a)
        + trapezoid_time(distance, limits.max_linear_speed, limits.max_linear_accel)
        + trapezoid_time(wrap_angle(goal_theta - facing), w, a)
    )
