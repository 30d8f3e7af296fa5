"""What ``verify`` measures time with: the machine's monotonic clock, or the simulated time of
a system run with ``launch --time-scale`` (its ``clock`` key, as a node with ``use_sim_time``
follows it), so that a 5-minute criterion takes one minute of wall clock at 5x and a goal's
time is in the simulated seconds its ``time_taken`` is in."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from turtlectl.messages import Clock
from turtlectl.messages.keys import CLOCK
from turtlectl.runtime.client.api import Client
from turtlectl.runtime.client.errors import TurtlectlError, Unreachable
from turtlectl.runtime.simtime import SimClock

#: s of wall clock to wait for a system's first Clock
FIRST_CLOCK = 5.0


class Timebase:
    """The machine's clock: ``now()`` monotonic s, ``sleep(s)``."""

    factor = 1.0  # its s per wall s

    def now(self) -> float:
        return time.monotonic()

    def sleep(self, seconds: float) -> None:
        time.sleep(max(0.0, seconds))  # pacing: a measuring window of the machine's time

    def close(self) -> None:
        """Nothing to let go of."""


class SimulatedTime(Timebase):
    """A system's simulated time (s since the epoch), from its ``clock``, as a node with
    ``use_sim_time`` keeps it (runtime.simtime.SimClock: between two Clocks it runs on at their
    factor, by at most a step)."""

    def __init__(self, client: Client):
        self._heard = threading.Event()
        self._clock = SimClock(wake=lambda: None, rejected=lambda _: None)
        self._sub = client.subscribe(CLOCK, self._on_clock)
        if not self._heard.wait(FIRST_CLOCK):
            self._sub.undeclare()
            raise Unreachable(
                f"nothing publishes {CLOCK} at {client.connect} within {FIRST_CLOCK:g} s: a simulator makes the "
                "simulated time (launch --time-scale, or any simulator of turtlectl)"
            )

    @property
    def factor(self) -> float:  # type: ignore[override]
        return self._clock.real_time_factor

    def _on_clock(self, message: object) -> None:  # Zenoh's thread
        if isinstance(message, Clock):
            self._clock.heard_clock(message)
            self._heard.set()

    def now(self) -> float:
        return self._clock.now()

    def sleep(self, seconds: float) -> None:
        until = self.now() + seconds
        while (left := until - self.now()) > 0:
            time.sleep(min(0.05, left / max(self.factor, 0.1)))  # pacing: the simulated time goes by

    def close(self) -> None:
        self._sub.undeclare()


#: s: how long verify listens for a system's clock to learn whether it runs in simulated time
PEEK = 0.5


def system_time(client: Client, asked: bool, progress: Callable[[str], None]) -> Timebase:
    """What ``verify`` measures with: the system's simulated time when ``asked`` (--use-sim-time,
    --time-scale) or when its clock runs at another factor than 1 (a system started with
    ``launch --time-scale``: the machine's clock would misread every time in it); else the machine's."""
    if asked:
        return SimulatedTime(client)
    try:
        clock = client.latest(CLOCK, timeout=PEEK)
    except TurtlectlError:
        return Timebase()  # no simulator's clock: the machine's time
    if isinstance(clock, Clock) and clock.real_time_factor != 1.0:
        progress(f"the system's clock runs at {clock.real_time_factor:g}x: measuring in its simulated time")
        return SimulatedTime(client)
    return Timebase()
