"""The node's one thread (``runtime.node.Node`` runs on it): timers on their absolute grid and
the callbacks Zenoh's threads queue, one at a time, until ``stop``; then the shutdown hooks.
A node's time is its ``clock`` (the machine's monotonic s, a fake one under ``runtime.fake``,
or the simulated one with ``use_sim_time``: runtime.simtime wakes the thread when a Clock
passes the next deadline)."""

from __future__ import annotations

import logging
import queue
from collections.abc import Callable
from typing import Any

from turtlectl.runtime.entities import Timer
from turtlectl.runtime.simtime import SimClock


class NodeLoop:
    """What runs a ``Node``'s thread: ``spin``, ``stop``, ``shutdown`` (the attributes below are
    the node's, set by ``Node.__init__``)."""

    _running: bool
    _queue: queue.SimpleQueue[tuple[Callable[..., None], tuple[Any, ...]]]
    _timers: list[Timer]
    _on_shutdown: list[Callable[[], None]]
    _sim: SimClock | None
    clock: Callable[[], float]
    log: logging.Logger

    @property
    def stopping(self) -> bool:
        """Whether ``stop`` was asked for (a signal, the parent's death, the node itself)."""
        return not self._running

    def stop(self, *_: Any) -> None:
        """Ask the node to stop (safe from signal handlers and other threads)."""
        self._running = False
        self._queue.put((lambda: None, ()))

    def spin(self) -> bool:
        """Run timers and queued callbacks on this thread until ``stop``, then the shutdown
        hooks.  Returns False if node code raised: the traceback is logged once and the
        node stops as if asked to (its hooks still run, so a navigator still stops the turtle)."""
        ok = True
        # this loop runs at the fastest timer's rate (the simulator's 62.5 Hz): names bound once,
        # no generator per turn
        timers, get, clock, empty, fire_due = self._timers, self._queue.get, self.clock, queue.Empty, self._fire_due
        sim = self._sim
        try:
            while self._running:
                now = clock()
                fire_due(now)
                wake = now + 1.0
                for t in timers:  # after every callback: one may have paused or resumed a timer
                    if t.active and t.deadline < wake:
                        wake = t.deadline
                if sim is not None:  # simulated time: the next Clock past ``wake`` wakes the thread
                    sim.wake_at = wake
                    sim.say_if_waiting(self.log)
                try:
                    func, args = get(timeout=sim.timeout(wake) if sim is not None else max(0.0, wake - clock()))
                except empty:
                    continue
                func(*args)
        except Exception:  # node code: a defect, reported once; stop cleanly and let respawn apply
            self.log.exception("stopping after an error in node code")
            ok = False
        self.shutdown()
        return ok

    def _fire_due(self, now: float) -> None:
        """Run every active timer due at ``now`` (one step of ``spin``; ``runtime.fake`` too)."""
        for t in self._timers:
            if t.active and now >= t.deadline:
                t.advance(now)
                t.callback()

    def _drain(self) -> None:
        """Run everything queued, and what that queues, without waiting (``runtime.fake``).
        Node code that raises propagates; what is still queued stays queued."""
        get, empty = self._queue.get_nowait, queue.Empty
        while True:
            try:
                func, args = get()
            except empty:
                return
            func(*args)

    def shutdown(self) -> None:
        """Run the shutdown hooks once, each even if an earlier one raised."""
        hooks, self._on_shutdown = self._on_shutdown, []
        self._running = False
        for callback in hooks:
            try:
                callback()
            except Exception:  # one failing hook must not keep the next (e.g. the stop command) from running
                self.log.exception("shutdown hook %s failed", getattr(callback, "__qualname__", callback))
