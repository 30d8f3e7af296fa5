"""Simulated time for a node started with ``use_sim_time`` (ROS's parameter of that name):
the node's clock follows the ``Clock`` messages the simulator publishes on ``clock`` after
every step, instead of the machine's clock.

Its timers, the timeouts its code measures with ``node.clock()`` and the stamps of what it
publishes all follow the simulated time, so a simulator running 5 times as fast as the wall
clock (its ``real_time_factor``) makes the whole system run 5 times as fast, and one slowed by a
busy machine slows the nodes with it.  Until the first ``Clock`` arrives the time is 0 (as in
ROS): no timer of the node is due, and what it publishes is stamped 0.

Between two Clocks the time runs on at their factor, by at most one step (SimClock).

Units: ``now()`` in s, ``now_ns()`` in ns, both since the Unix epoch (the simulated clock starts
at the wall-clock time its simulator started).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

from turtlectl.messages import Clock, decode
from turtlectl.messages.keys import CLOCK
from turtlectl.runtime.declarations import SUBSCRIPTION
from turtlectl.runtime.handles import Declaration

if TYPE_CHECKING:
    from turtlectl.runtime.core import NodeCore

#: s: with use_sim_time, how long a node waits for the first Clock before it says so
WAIT_FOR_CLOCK = 3.0

#: ns: a Clock this much older than the last is a jump back (a replay looping, a simulator
#: started again), which the node's time follows; a less old one is a late one, ignored
JUMP_BACK = 1_000_000_000


class SimClock:
    """The simulated time: the newest ``Clock`` heard (a late one never takes it back; a jump of
    more than JUMP_BACK back does, and ``restarted`` is told, as ROS's time jump), running on at its
    ``real_time_factor`` until the next one, by at most the gap between the last two (one step of
    the simulator: a timer of 100 ms fires at 100 ms of simulated time, not at the 16 ms step
    after it, and a stalled simulator stops the time within a step).  Wakes the node's thread
    when a Clock passes its next timer deadline (``wake_at``, s)."""

    def __init__(
        self,
        wake: Callable[[], None],
        rejected: Callable[[str], None],
        monotonic: Callable[[], float] = time.monotonic,
        restarted: Callable[[float], None] | None = None,
    ):
        #: told (on a Zenoh thread) that the time began or jumped back (s back; 0.0 the first time):
        #: the new time holds off until the node's thread ``accept``s it (so no timer of its fires on
        #: the old grid meanwhile).  None: the new time holds at once.
        self._restarted = restarted
        self._pending: tuple[int, float, int, float] | None = None
        self._say_by: float | None = monotonic() + WAIT_FOR_CLOCK  # s: say so if no Clock came by then
        self.declared: Declaration | None = None  # a node's subscription to ``clock`` (follow_clock)
        self._monotonic = monotonic  # s: the machine's clock, to run on between two Clocks
        #: (ns of the last Clock, monotonic s it came, ns since the one before, its factor)
        self._base = (0, 0.0, 0, 1.0)
        self._last = 0  # ns: the latest time given (never less after)
        self.wake_at = math.inf  # s: the node's next deadline, set by its loop before it waits
        self._wake = wake  # queues a no-op for the node's thread (it then fires what is due)
        self._rejected = rejected  # a malformed payload on ``clock``: counted and logged

    @property
    def real_time_factor(self) -> float:
        """Simulated s per wall s, as the last Clock said."""
        return self._base[3]

    def now_ns(self) -> int:
        """The simulated time in ns (0 before the first Clock)."""
        ns, heard, step, factor = self._base
        if ns == 0:
            return 0
        ahead = min(round((self._monotonic() - heard) * factor * 1e9), step)
        self._last = max(self._last, ns + ahead)
        return self._last

    def now(self) -> float:
        """The simulated time in s (0.0 before the first Clock)."""
        return self.now_ns() / 1e9

    def timeout(self, wake: float) -> float:
        """Wall s the node's thread may sleep before its deadline ``wake`` (simulated s) comes,
        as far as the time can run on without a new Clock; beyond that a Clock wakes it."""
        ns, _, step, factor = self._base
        now = self.now()
        if wake <= now:
            return 0.0
        if ns == 0 or now >= (ns + step) / 1e9:  # no time to run on: the next Clock wakes it
            return 1.0
        return min(1.0, (min(wake, (ns + step) / 1e9) - now) / factor)

    def heard(self, payload: bytes) -> None:
        """A ``Clock`` payload arrived (on a Zenoh thread): move the time on, and wake the node's
        thread if a deadline of its is due."""
        try:
            clock = decode(payload, Clock)
        except ValueError as exc:
            self._rejected(str(exc))
            return
        self.heard_clock(clock)

    def say_if_waiting(self, log: logging.Logger) -> None:
        """Once, WAIT_FOR_CLOCK s after it was made: log that no Clock came yet, if none did."""
        if self._say_by is not None and self._monotonic() > self._say_by:
            self._say_by = None
            if not self._base[0] and self._pending is None:
                log.warning("no clock yet (use_sim_time): its timers wait for a simulator to publish %s", CLOCK)

    def accept(self) -> None:
        """On the node's thread: the time that began or jumped back holds from now on."""
        pending, self._pending = self._pending, None
        if pending is not None:
            self._base, self._last = pending, pending[0]

    def heard_clock(self, clock: Clock) -> None:
        """A ``Clock`` (decoded) arrived: as ``heard``."""
        last = (self._pending or self._base)[0]
        back = last - clock.clock
        if 0 <= back <= JUMP_BACK:  # a late or repeated one: the time never goes back for it
            return
        restarting = not last or back > 0  # the time begins, or a replay looped
        step = 0 if restarting else min(clock.clock - last, 1_000_000_000)
        base = (clock.clock, self._monotonic(), step, clock.real_time_factor)
        if self._restarted is not None and (restarting or self._pending is not None):
            self._pending = base  # held for the node's thread (accept)
            if restarting:
                self._restarted(back / 1e9 if last else 0.0)
            return
        self._base = base
        if restarting:
            self._last = clock.clock
        if clock.clock / 1e9 >= self.wake_at:
            self._wake()


def follow_clock(core: NodeCore) -> SimClock:
    """Put the node of ``core`` on the simulator's clock (``use_sim_time``): its ``clock()``, its
    timers and its stamps follow the ``Clock`` messages on ``clock``; when the time begins or jumps
    back, its timers start again from it (on its own thread).  The subscription is the runtime's
    own (``list`` shows it); ``Node.use_time`` undeclares it for a node that makes the time itself."""
    enqueue = core.enqueue
    sim = SimClock(
        lambda: enqueue(_nothing),
        lambda why: enqueue(core.reject, CLOCK, why),
        restarted=lambda back: enqueue(_restarted, core, sim, back),
    )
    core.set_time_source(sim.now, sim.now_ns, sim)

    def build(declared: Declaration) -> Declaration:
        declared.add(core.session.declare_subscriber(CLOCK, lambda sample: sim.heard(sample.payload.to_bytes())))
        return declared

    sim.declared = core.declare(SUBSCRIPTION, CLOCK, (Clock,), build, own=True)
    return sim


def _nothing() -> None:
    """A queue item that only wakes the node's thread (it then fires what is due)."""


def _restarted(core: NodeCore, sim: SimClock, back: float) -> None:
    """The simulated time began (``back`` 0.0) or jumped back ``back`` s: every timer of the node
    starts again from it, its first tick a period on (ROS resets its timers on a jump back)."""
    if core.sim is not sim:  # it makes the time itself meanwhile (use_time)
        return
    sim.accept()
    core.restart_timers(core.clock())
    if back:
        core.log.warning("the clock went back %.3f s (a replay looping?): timers start again from it", back)
