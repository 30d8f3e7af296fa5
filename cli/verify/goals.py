"""The goal criteria of a specification, measured through a ``turtlectl.Client``: goals reached
within a time, a distance and a heading (``goal``), from a given start and with seeded random
goals; a goal's reported ``time_taken`` against the client's own clock (``reported_time``)."""

from __future__ import annotations

import math
import random

from turtlectl.cli.verify.report import Verdict
from turtlectl.cli.verify.spec import Goals, Pose, ReportedTime, label
from turtlectl.cli.verify.timebase import Timebase
from turtlectl.messages import TeleportAbsolute
from turtlectl.messages.angles import heading_difference_degrees, heading_radians
from turtlectl.messages.keys import TELEPORT
from turtlectl.runtime.client.api import Client
from turtlectl.runtime.client.errors import TurtlectlError


def goal_list(c: Goals | ReportedTime) -> list[Pose]:
    """The criterion's goals (x m, y m, theta degrees): those given, then ``random`` more drawn
    with ``seed`` in ``area`` (the same for the same seed)."""
    goals = list(c.goals)
    if isinstance(c, Goals) and c.random > 0:
        draw = random.Random(c.seed)
        x0, y0, x1, y1 = c.area
        goals += [
            (round(draw.uniform(x0, x1), 2), round(draw.uniform(y0, y1), 2), round(draw.uniform(0, 360), 1))
            for _ in range(c.random)
        ]
    return goals


def heading_error(a: float, b: float) -> float:
    """How far apart two headings in degrees are, in [0, 180] degrees."""
    return heading_difference_degrees(heading_radians(a), heading_radians(b))


def goals(client: Client, c: Goals | ReportedTime, clock: Timebase | None = None) -> Verdict:
    """Each goal of ``c`` through the client, timed on ``clock`` (the machine's by default; a
    system's simulated time, in which its time_taken is, with ``verify --time-scale``)."""
    clock = clock or Timebase()
    worst_time, worst_distance, worst_heading, worst_gap, problems = 0.0, 0.0, 0.0, 0.0, []
    answered = 0
    for x, y, theta in goal_list(c):
        try:
            if isinstance(c, Goals) and c.start is not None:
                sx, sy, stheta = c.start
                client.call(TELEPORT, TeleportAbsolute(x=sx, y=sy, theta=heading_radians(stheta)))
            started = clock.now()
            response = client.goto(x, y, theta, timeout=max(c.within_s * 5, 30.0))
        except TurtlectlError as exc:
            problems.append(f"({x:g}, {y:g}): {exc.message}")
            continue
        elapsed = clock.now() - started
        answered += 1
        worst_time = max(worst_time, elapsed)
        worst_gap = max(worst_gap, abs(elapsed - response.time_taken))
        if not response.success:
            problems.append(f"({x:g}, {y:g}) not reached: {response.reason}")
        if isinstance(c, Goals):
            distance = math.hypot(response.x - x, response.y - y)
            heading = heading_error(response.theta, theta)
            worst_distance, worst_heading = max(worst_distance, distance), max(worst_heading, heading)
            if elapsed > c.within_s:
                problems.append(f"({x:g}, {y:g}) took {elapsed:.2f} s, {elapsed - c.within_s:.2f} s too long")
            if distance > c.distance_m:
                problems.append(f"({x:g}, {y:g}) ended {distance:.3f} m away")
            if c.heading_deg is not None and heading > c.heading_deg:
                problems.append(f"({x:g}, {y:g}) ended {heading:.1f} deg off its heading")
        elif abs(elapsed - response.time_taken) > c.within_s:
            problems.append(f"({x:g}, {y:g}) reported {response.time_taken:.3f} s, the client measured {elapsed:.3f} s")
    if isinstance(c, Goals):
        heading = "" if c.heading_deg is None else f", {c.heading_deg:g} deg"
        required = f"each within {c.within_s:g} s, {c.distance_m:g} m{heading}"
        measured = f"slowest {worst_time:.2f} s, farthest {worst_distance:.3f} m"
        measured += "" if c.heading_deg is None else f", {worst_heading:.1f} deg"
        measured = measured if answered else "no goal answered"
    else:
        required = f"|time_taken - client's time| <= {c.within_s:g} s"
        measured = f"largest gap {worst_gap:.3f} s" if answered else "no goal answered"
    return Verdict(label(c), required, measured, not problems, "; ".join(problems))
