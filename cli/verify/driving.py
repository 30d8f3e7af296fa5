"""Goals driven one after another while a ``no_errors`` criterion runs, so that it measures a
navigator at work rather than idle: the goals the criterion lists, in turn and over again, or
random ones drawn from its seed in the world the simulator declares, clear of the walls and
of every declared obstacle.  ``goal_sequence``, ``random_goal`` and ``Outcomes`` are pure;
``GoalDriver`` drives them through a ``turtlectl.Client`` on a thread of its own."""

from __future__ import annotations

import itertools
import math
import random
import threading
from collections import Counter
from collections.abc import Iterator

from turtlectl.cli.verify.spec import NoErrors, Pose
from turtlectl.messages import NavigateToResponse
from turtlectl.messages.world import World
from turtlectl.runtime.client.api import Client
from turtlectl.runtime.client.errors import GoalCanceled, TurtlectlError

#: m: how far a random goal stays from a wall and from an obstacle's edge (the turtle's radius,
#: the navigator's clearance and safety distance, with room to turn)
MARGIN = 1.0
#: draws before a world is declared too full for a random goal
TRIES = 1000
#: s between two goals after one whose call erred (a navigator gone must not make a busy loop)
AFTER_ERROR = 1.0
#: s a goal has to end once canceled at the end of the criterion
CANCEL_WAIT = 10.0


def random_goal(draw: random.Random, world: World, margin: float = MARGIN) -> Pose:
    """A goal (x m, y m, theta degrees) at least ``margin`` from the walls and from every
    obstacle's edge; ValueError when ``TRIES`` draws find none (a world too small or too full)."""
    low, high = margin, world.size - margin
    if low < high:
        for _ in range(TRIES):
            x, y = draw.uniform(low, high), draw.uniform(low, high)
            if all(math.hypot(x - o.x, y - o.y) >= o.radius + margin for o in world.obstacles):
                return round(x, 2), round(y, 2), round(draw.uniform(-180.0, 180.0), 1)
    raise ValueError(f"no goal {margin:g} m clear of the walls and obstacles in {TRIES} draws")


def goal_sequence(c: NoErrors, world: World) -> Iterator[Pose]:
    """The goals to drive, without end: ``c.goals`` over and over, or random ones from ``c.seed``
    (the same goals for the same seed and world); none when the criterion drives no goals."""
    if c.goals:
        return itertools.cycle(c.goals)
    if c.random_goals:
        draw = random.Random(c.seed)
        return (random_goal(draw, world) for _ in itertools.count())
    return iter(())


class Outcomes:
    """How the goals driven ended: reached, not reached (by the navigator's reason), canceled
    when the criterion's time was up, and the calls that erred (what went wrong)."""

    def __init__(self) -> None:
        self.reached = 0
        self.unreached: Counter[str] = Counter()
        self.canceled = 0
        self.erred: list[str] = []

    @property
    def driven(self) -> int:
        return self.reached + sum(self.unreached.values()) + self.canceled + len(self.erred)

    def summary(self) -> str:
        """``12 goals driven: 10 reached, 1 not reached (blocked 1), 1 canceled at the end``."""
        parts = [f"{self.reached} reached"]
        if self.unreached:
            reasons = ", ".join(f"{why} {n}" for why, n in sorted(self.unreached.items()))
            parts.append(f"{sum(self.unreached.values())} not reached ({reasons})")
        if self.canceled:
            parts.append(f"{self.canceled} canceled at the end")
        if self.erred:
            parts.append(f"{len(self.erred)} erred")
        driven = self.driven
        return f"{driven} goal{'s' * (driven != 1)} driven: {', '.join(parts)}"

    def problems(self, shown: int = 3) -> list[str]:
        """The calls that erred, the first ``shown`` of them named: each fails the criterion."""
        if not self.erred:
            return []
        more = [f"and {len(self.erred) - shown} more"] if len(self.erred) > shown else []
        return [f"goal {e}" for e in self.erred[:shown]] + more


class GoalDriver:
    """Drives ``goals`` through ``client.goto`` one after another on its own thread from
    ``start()`` until ``stop()``, which cancels the goal still running and returns the outcomes."""

    def __init__(self, client: Client, goals: Iterator[Pose]):
        self._client = client
        self._goals = goals
        self._stopping = threading.Event()
        self._outcomes = Outcomes()
        self._thread = threading.Thread(target=self._drive, name="verify-goals", daemon=True)
        self._in_flight = threading.Event()

    def start(self) -> GoalDriver:
        self._thread.start()
        return self

    def _drive(self) -> None:
        out = self._outcomes
        for x, y, theta in self._goals:
            if self._stopping.is_set():
                return
            self._in_flight.set()
            if self._stopping.is_set():  # stop() may have looked before in_flight was set
                return
            try:
                response = _outcome(self._client, x, y, theta)
            except TurtlectlError as exc:
                self._in_flight.clear()
                if self._stopping.is_set():
                    out.canceled += 1
                    return
                out.erred.append(f"({x:g}, {y:g}, {theta:g}): {exc.message}")
                self._stopping.wait(AFTER_ERROR)
                continue
            self._in_flight.clear()
            if response.success:
                out.reached += 1
            elif self._stopping.is_set():
                out.canceled += 1
            else:
                out.unreached[response.reason or "no reason given"] += 1

    def stop(self) -> Outcomes:
        """No goal after this; the one running canceled (and its cancel confirmed); the outcomes."""
        self._stopping.set()
        if self._in_flight.is_set():
            try:
                self._client.cancel()
            except TurtlectlError as exc:
                self._outcomes.erred.append(f"canceled at the end: {exc.message}")
        self._thread.join(CANCEL_WAIT)
        if self._thread.is_alive():
            self._outcomes.erred.append(f"the last goal did not end within {CANCEL_WAIT:g} s of its cancel")
        return self._outcomes


def _outcome(client: Client, x: float, y: float, theta: float) -> NavigateToResponse:
    """The navigator's answer to a goal, a canceled one's too (``GoalCanceled`` carries it)."""
    try:
        return client.goto(x, y, theta)
    except GoalCanceled as exc:
        if exc.response is None:
            raise
        return exc.response
