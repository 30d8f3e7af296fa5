"""The other turtles as a navigator meets them: where they are, and for those it gives way to,
where they are about to be.  Pure: the clock passed in.

The scan (5 Hz) sees another turtle where it was up to 0.2 s ago, and a turtle crossing from
the side enters the corridor ahead only when it is nearly there: at 4 m/s two turtles on
crossing paths would meet before either slowed.  So each navigator also reads ``turtles``
(every turtle's pose, 15.6 Hz) and adds, to what its corridor check sees:

- every other turtle's body where it is now (points round its centre, at the turtle radius);
- for a turtle it gives way to (one whose name sorts before its own: turtle1 before turtle2,
  the same order in every navigator, so two never wait for each other), the bodies it will
  sweep over the next ``HORIZON`` s at its present velocity (estimated from two poses), while
  it moves.  The turtle giving way slows and stops short of the other's way, and drives on
  once it has passed; the one with the right of way drives on, and still stops for a body in
  its way.

A scan's hits on another turtle are not remembered as obstacles (the costmap would keep a
moving turtle's trail as a wall): the planner goes round the others where they are now.

Units: m, s, rad.
"""

from __future__ import annotations

import math

import numpy as np

from turtlectl.messages import Turtles

#: s ahead that a turtle with the right of way is expected to sweep
HORIZON = 1.2
#: s between two predicted bodies
STEP = 0.1
#: m/s below which a turtle counts as standing (its body alone, no sweep)
STANDING = 0.05
#: s after which what ``turtles`` said is too old to use
STALE = 0.5
#: s: how old a scan's hits may be when a turtle's body explains them
SCAN_AGE = 0.3
#: points on each body's outline
RING = 12

_ANGLES = np.linspace(0.0, 2.0 * math.pi, RING, endpoint=False)
_RING = np.stack([np.cos(_ANGLES), np.sin(_ANGLES)], axis=1)


def gives_way(own: str, other: str) -> bool:
    """Whether turtle ``own`` gives way to ``other`` (the same answer in every navigator)."""
    return other < own


class Traffic:
    """What ``turtles`` last said of the others, and their velocities (m/s) from the two
    latest messages."""

    def __init__(self, own: str, radius: float):
        self.own = own
        self.radius = radius  # m: a turtle's (World.turtle_radius)
        self.time = -math.inf  # s: when the latest message came
        self.stamp = 0  # ns: its stamp (the simulator's clock)
        self.others: dict[str, tuple[float, float, float, float]] = {}  # name -> x, y, vx, vy

    def update(self, msg: Turtles, now: float) -> None:
        """A ``turtles`` message received at ``now`` s (velocities from the time between its
        stamp and the previous one's, else between their arrivals)."""
        dt = (msg.stamp - self.stamp) / 1e9 if msg.stamp and self.stamp else now - self.time
        self.stamp = msg.stamp
        others: dict[str, tuple[float, float, float, float]] = {}
        for name, x, y in zip(msg.names, msg.x, msg.y, strict=False):
            if name == self.own:
                continue
            before = self.others.get(name)
            vx = vy = 0.0
            if before is not None and 0.0 < dt < STALE:
                vx, vy = (x - before[0]) / dt, (y - before[1]) / dt
            others[name] = (x, y, vx, vy)
        self.others, self.time = others, now

    def centres(self, now: float) -> list[tuple[float, float, float]]:
        """Where the other turtles are now (x, y m, and their speed m/s), from the latest
        ``turtles`` carried forward at their velocities; none when it has gone stale."""
        if now - self.time > STALE:
            return []
        late = now - self.time
        return [(x + vx * late, y + vy * late, math.hypot(vx, vy)) for x, y, vx, vy in self.others.values()]

    def explains(self, points: np.ndarray, now: float) -> np.ndarray:
        """Which of scan hits ``points`` (n, 2), m, are another turtle's body (a bool mask): within
        the turtle radius of where one is, with room for how far it moved since the scan (up
        to SCAN_AGE s old)."""
        mask = np.zeros(len(points), dtype=bool)
        for x, y, speed in self.centres(now):
            reach = self.radius + 0.1 + speed * SCAN_AGE
            mask |= np.hypot(points[:, 0] - x, points[:, 1] - y) <= reach
        return mask

    def points(self, now: float) -> np.ndarray:
        """Points (n, 2), m, on the outlines of the other turtles now and, for those this one
        gives way to, over the next HORIZON s; none when ``turtles`` has gone stale."""
        if now - self.time > STALE or not self.others:
            return np.zeros((0, 2))
        late = now - self.time  # the message is this old: everyone has moved on since
        centres: list[tuple[float, float]] = []
        for name, (x, y, vx, vy) in self.others.items():
            moving = math.hypot(vx, vy) > STANDING
            centres.append((x + vx * late, y + vy * late))
            if moving and gives_way(self.own, name):
                for t in np.arange(STEP, HORIZON + 1e-9, STEP):
                    centres.append((x + vx * (late + t), y + vy * (late + t)))
        c = np.asarray(centres, dtype=float)
        return (c[:, None, :] + self.radius * _RING[None, :, :]).reshape(-1, 2)
