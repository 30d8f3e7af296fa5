"""The navigator's control law as pure functions: no I/O, no clock, no zenoh.

A goal is reached in two phases: DRIVE to the position (turning while driving,
backwards when the goal is behind), then ALIGN to the final heading in place.
Speeds follow a "brake in time" profile: v = min(v_max, sqrt(2 a d), k d), so
the turtle cruises, brakes, and settles without overshoot.

Units: m, rad, m/s, rad/s, s.
"""

from __future__ import annotations

import enum
import math

import msgspec

from sim.kinematics import wrap_angle
from sim.world import Limits, Positive


class Phase(enum.StrEnum):
    DRIVE = "driving"
    ALIGN = "aligning"
    DONE = "done"


class Gains(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """Tuning of the control law (units in the field comments)."""

    k_linear: Positive = 10.0  # 1/s: speed per metre of distance near the goal
    k_angular: Positive = 20.0  # 1/s: turn rate per radian of heading error near the target
    linear_decel: Positive = 10.0  # m/s^2: braking used to plan the approach
    angular_decel: Positive = 40.0  # rad/s^2: braking used to plan the final turn
    drive_cone: Positive = math.radians(60.0)  # rad: beyond this heading error, turn before driving


class Command(msgspec.Struct, kw_only=True):
    """Output of one control step: velocities (m/s, rad/s) and the phase after it."""

    linear: float
    angular: float
    phase: Phase
    reverse: bool = False


def _profile(error: float, v_max: float, decel: float, k: float) -> float:
    """Speed magnitude that brakes to rest exactly at ``error`` (>= 0) away."""
    return min(v_max, math.sqrt(2.0 * decel * error), k * error)


def control_step(
    x: float,
    y: float,
    theta: float,
    goal_x: float,
    goal_y: float,
    goal_theta: float,
    phase: Phase,
    limits: Limits,
    gains: Gains,
    position_tolerance: float,
    heading_tolerance: float,
) -> Command:
    """One step of the control law from the current pose (m, m, rad) to the goal (m, m, rad).

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

    if phase is Phase.DRIVE:
        alpha = wrap_angle(math.atan2(dy, dx) - theta)
        reverse = abs(alpha) > math.pi / 2.0
        if reverse:
            alpha = wrap_angle(alpha + math.pi)
        angular = math.copysign(
            _profile(abs(alpha), limits.max_angular_speed, gains.angular_decel, gains.k_angular), alpha
        )
        if abs(alpha) >= gains.drive_cone:
            speed = 0.0
        else:
            # Project the speed on the heading, and fade it out towards the cone's edge.
            speed = _profile(distance, limits.max_linear_speed, gains.linear_decel, gains.k_linear)
            speed *= math.cos(alpha) * (1.0 - abs(alpha) / gains.drive_cone)
        return Command(linear=-speed if reverse else speed, angular=angular, phase=phase, reverse=reverse)

    error = wrap_angle(goal_theta - theta)
    if abs(error) <= 0.5 * heading_tolerance:
        return Command(linear=0.0, angular=0.0, phase=Phase.DONE)
    angular = math.copysign(
        _profile(abs(error), limits.max_angular_speed, gains.angular_decel, gains.k_angular), error
    )
    return Command(linear=0.0, angular=angular, phase=Phase.ALIGN)
