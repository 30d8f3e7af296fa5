"""Angles as people and the wire see them: the one place headings are reduced.

Degrees are what people type and read (``goto``, ``TurtleStatus.theta``, feedback);
radians are what the kinematics use.  No other module converts or reduces them (a unit
test reads the source for ``math.degrees``, ``% 360`` and ``fmod`` elsewhere).  A heading that enters the system in degrees is
reduced in degrees first (``math.fmod`` is exact), so ``1e16`` or ``1e308`` degrees
become an ordinary heading instead of a radian value whose last bits are noise.
"""

from __future__ import annotations

import math


def degrees_0_360(degrees: float) -> float:
    """``degrees`` reduced to [0, 360) exactly (fmod); NaN and inf stay as they are."""
    if not math.isfinite(degrees):
        return degrees
    reduced = math.fmod(degrees, 360.0)
    if reduced < 0.0:
        reduced += 360.0
    return 0.0 if reduced >= 360.0 else reduced  # -1e-17 + 360 rounds to 360.0


def heading_degrees(radians: float) -> float:
    """A heading in rad as people read it: degrees in [0, 360)."""
    return degrees_0_360(math.degrees(radians))


def heading_difference_degrees(a: float, b: float) -> float:
    """How far apart two headings in rad are: degrees in [0, 180]."""
    return abs(math.degrees(wrap_radians(a - b)))


def heading_radians(degrees: float) -> float:
    """A heading typed in degrees (any finite value) as rad in [-pi, pi)."""
    return wrap_radians(math.radians(degrees_0_360(degrees)))


def wrap_radians(angle: float) -> float:
    """``angle`` (rad) wrapped into [-pi, pi); exact for any finite value (math.remainder)."""
    wrapped = math.remainder(angle, 2.0 * math.pi)  # in [-pi, pi]
    return -math.pi if wrapped >= math.pi else wrapped
