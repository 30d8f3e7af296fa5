"""This project's own module named ``messages`` (as many projects have one): turtlectl's are
``turtlectl.messages``, so neither hides the other."""

from __future__ import annotations

import math

import msgspec


class Corner(msgspec.Struct, frozen=True):
    """A corner of the patrol's square: where to go (m, m) and which way to face (degrees)."""

    x: float
    y: float
    theta: float


def square(cx: float, cy: float, side: float) -> list[Corner]:
    """The four corners of a square of ``side`` m centred on (``cx``, ``cy``) m, counter-clockwise
    from the lower left; each faces along the next side (degrees)."""
    h = side / 2.0
    points = [(cx - h, cy - h), (cx + h, cy - h), (cx + h, cy + h), (cx - h, cy + h)]
    corners = []
    for i, (x, y) in enumerate(points):
        nx, ny = points[(i + 1) % 4]
        corners.append(Corner(x, y, math.degrees(math.atan2(ny - y, nx - x))))
    return corners
