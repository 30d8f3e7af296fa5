"""The node's core: what a ``runtime.node.Node`` is made of below its API, as rclpy's executor is
apart from its node.  One ``NodeCore`` per node owns

* the queue: callbacks handed over by Zenoh's threads (``enqueue``), run one at a time on the
  node's thread by ``run`` (until ``stop``), ``run_once`` or ``drain``;
* the timers (``timer``), fired on their absolute grid by ``fire_due``;
* the time source: ``clock()`` (s, what timers run on) and ``now_ns()`` (ns since the epoch, what
  messages are stamped with), swapped together by ``set_time_source`` (runtime.simtime);
* the declarations: ``declare(kind, key, types, build)`` is the one path of every declaration
  (a node's, the runtime's own, a new kind's), and ``reject`` counts and logs bad payloads.

The contract, which every user of the core (``Node``, runtime.declarations, runtime.simtime,
runtime.own_services, runtime.log_stream, runtime.fake) keeps to:

* ``enqueue`` and ``stop`` may be called from any thread; everything else runs on the node's
  thread (the one that calls ``run``, ``run_once`` or ``drain``).
* A callback runs only on the node's thread, one at a time, in the order it was queued; an
  exception from one propagates out of ``drain``/``run_once`` and ends ``run`` (logged once).
* A timer is due when ``clock() >= deadline``; ``fire_due`` fires each due one once and moves
  it on its grid (missed ticks skipped, not bunched).
* A declaration is checked against the node's interface (``runtime.interface``) before anything
  is declared, unless it is the runtime's own (``own=True``: what every node serves about
  itself, whatever its interface names); its graph token comes after its entities, so a tool
  that sees the token finds the entity.

A new declaration kind is a ``Kind`` and a function that calls ``declare`` (see
runtime.declarations for the node's own kinds)."""

from __future__ import annotations

import logging
import os
import queue
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TypeVar

from turtlectl.messages import Message
from turtlectl.messages.codec import type_name
from turtlectl.messages.keys import EntityInfo, entity_token, resolve
from turtlectl.runtime.config import Interface
from turtlectl.runtime.entities import Timer
from turtlectl.runtime.handles import Declaration
from turtlectl.runtime.interface import check

if TYPE_CHECKING:
    import zenoh

    from turtlectl.runtime.simtime import SimClock

H = TypeVar("H")


@dataclass(frozen=True)
class Kind:
    """What a declaration is.  ``what``: its handle's name ("publisher", "subscription");
    ``verb``: what the node's interface must let it do on its key (runtime.interface.FIELDS:
    "publish", "subscribe", "serve", "call", "watch"; None: nothing to check); ``roles``: the
    graph tokens it is shown by (``turtlectl list``), one per role, each with the type of the
    same place in ``declare``'s ``types`` (or ``type_name`` when it has no message type: "JSON")."""

    what: str
    verb: str | None
    roles: tuple[str, ...] = ()
    type_name: str = ""


class NodeCore:
    """The queue, timers, time source and declarations of the node ``name`` (see the module's
    docstring for the contract).  ``namespace`` and ``remaps`` resolve keys (``resolve``);
    ``interface``: what the node may declare (None: anything); ``clock`` (s) and ``time_ns``
    (ns since the epoch): the time source until ``set_time_source``."""

    def __init__(
        self,
        name: str,
        session: zenoh.Session,
        log: logging.Logger,
        clock: Callable[[], float],
        time_ns: Callable[[], int],
        *,
        namespace: str = "",
        remaps: Mapping[str, str] | None = None,
        interface: Interface | None = None,
    ):
        self.name = name
        self.session = session
        self.log = log
        self.namespace = namespace
        self.remaps: dict[str, str] = dict(remaps or {})
        self.interface = interface
        #: s: what timers run on (read it through this attribute: ``set_time_source`` swaps it)
        self.clock = clock
        self._time_ns = time_ns
        self._sim: SimClock | None = None
        self._queue: queue.SimpleQueue[tuple[Callable[..., None], tuple[Any, ...]]] = queue.SimpleQueue()
        self._timers: list[Timer] = []
        self._declarations: list[Declaration] = []  # declared, not yet undeclared
        self._bad_payloads: dict[str, int] = {}
        self._types: set[type[Message]] = set()
        self._on_type: Callable[[type[Message]], None] | None = None
        self._running = True
        self._on_shutdown: list[Callable[[], None]] = []

    # -- the time source ---------------------------------------------------------------------
    def now_ns(self) -> int:
        """The node's time in ns since the epoch (what its messages are stamped with)."""
        return self._time_ns()

    def set_time_source(
        self, clock: Callable[[], float], time_ns: Callable[[], int], sim: SimClock | None = None
    ) -> None:
        """Run timers on ``clock`` (s) and stamp with ``time_ns`` (ns) from now on.  ``sim``: the
        simulated clock they come from, which ``run`` tells its next deadline (a ``Clock`` past
        it wakes the thread) and asks how long it may sleep."""
        self.clock, self._time_ns, self._sim = clock, time_ns, sim

    @property
    def sim(self) -> SimClock | None:
        """The simulated clock the time comes from (``set_time_source``), or None."""
        return self._sim

    # -- declarations -------------------------------------------------------------------------
    def resolve(self, key: str) -> str:
        """The key this node uses for ``key`` as written (messages.keys.resolve: its namespace,
        then its remaps)."""
        return resolve(key, self.namespace, self.remaps)

    def declare(
        self,
        kind: Kind,
        key: str,
        types: Sequence[type[Message]],
        build: Callable[[Declaration], H],
        *,
        own: bool = False,
    ) -> H:
        """The one path of every declaration: ``key`` resolved; checked against the node's
        interface for ``kind.verb`` unless ``own`` (the runtime's own declarations, every
        node's whatever its interface: OutsideInterface otherwise); each of ``types`` made known
        (``uses``); a ``Declaration`` recorded among the node's (``declared.key`` is the resolved
        key); ``build(declared)`` makes the entities and adds them to it; then the graph tokens
        of ``kind.roles``.  Returns what ``build`` returns: the handle."""
        key = self.resolve(key)
        if kind.verb is not None and not own:
            check(self.name, self.interface, kind.verb, key)
        for msg_type in types:
            self.uses(msg_type)
        declared = Declaration(self._declarations, kind.what, key)
        handle = build(declared)
        names = [type_name(t) for t in types] or [kind.type_name]
        for role, name in zip(kind.roles, names, strict=False):
            declared.add(self.announce(role, name, key))
        return handle

    def announce(self, role: str, msg_type: type[Message] | str, key: str) -> zenoh.LivelinessToken:
        """A liveliness token for the graph (``turtlectl list``): this node's ``role`` on ``key``
        with a message type (or a type's name, such as "JSON").  ``declare`` makes a kind's;
        this is for an entity that is not a declaration (the log stream)."""
        name = msg_type if isinstance(msg_type, str) else type_name(msg_type)
        entity = EntityInfo(node=self.name, pid=os.getpid(), role=role, type_name=name, key=key)
        return self.session.liveliness().declare_token(entity_token(entity))

    def uses(self, msg_type: type[Message]) -> None:
        """The node uses ``msg_type``: the listener of ``on_type`` is told, once per type."""
        if msg_type in self._types:
            return
        if self._on_type is not None:
            self._on_type(msg_type)  # may raise (a second class under a known name): not recorded then
        self._types.add(msg_type)

    def on_type(self, listener: Callable[[type[Message]], None]) -> None:
        """Tell ``listener`` each message type the node uses (those used so far at once)
        (runtime.own_services describes them)."""
        self._on_type = listener
        for msg_type in list(self._types):
            listener(msg_type)

    def reject(self, key: str, reason: str) -> None:
        """A malformed payload on ``key``: counted, the first per key logged and then every 100th
        (on the node's thread: from another, ``enqueue(core.reject, key, reason)``)."""
        count = self._bad_payloads.get(key, 0) + 1
        self._bad_payloads[key] = count
        if count == 1 or count % 100 == 0:
            self.log.warning("dropped malformed payload #%d on %s: %s", count, key, reason)

    def rejections(self) -> dict[str, int]:
        """How many malformed payloads each key brought so far (a copy)."""
        return dict(self._bad_payloads)

    # -- timers ---------------------------------------------------------------------------------
    def timer(self, period: float, callback: Callable[[], None]) -> Timer:
        """A timer calling ``callback()`` every ``period`` s of ``clock`` from now, on its grid."""
        return Timer(period, callback, self.clock(), clock=self.clock, owner=self._timers)

    def fire_due(self, now: float) -> None:
        """Run every active timer due at ``now`` (s), each once, moved on its grid."""
        for t in self._timers:
            if t.active and now >= t.deadline:
                t.advance(now)
                t.callback()

    def next_deadline(self) -> float | None:
        """The earliest deadline of an active timer (s), None without one."""
        return min((t.deadline for t in self._timers if t.active), default=None)

    def restart_timers(self, now: float) -> None:
        """Every timer starts again from ``now``, its first tick a period on (a time source that
        began or jumped back)."""
        for timer in self._timers:
            timer.retime(timer.period, now)

    # -- the queue and the loop -----------------------------------------------------------------
    def enqueue(self, fn: Callable[..., None], *args: Any) -> None:
        """Run ``fn(*args)`` on the node's thread, after what is queued already (any thread)."""
        self._queue.put((fn, args))

    def pending(self) -> int:
        """How many callbacks are queued, not yet run."""
        return self._queue.qsize()

    def drain(self) -> None:
        """Run everything queued, and what that queues, without waiting and without firing
        timers (runtime.fake steps time itself).  What is still queued after an exception stays."""
        get, empty = self._queue.get_nowait, queue.Empty
        while True:
            try:
                func, args = get()
            except empty:
                return
            func(*args)

    def run_once(self, timeout: float = 0.0) -> bool:
        """One turn of ``run``: fire the timers due, then run one queued callback, waiting for
        one at most ``timeout`` s (and not past the next timer's deadline).  True if one ran."""
        now = self.clock()
        self.fire_due(now)
        deadline = self.next_deadline()
        wait = timeout if deadline is None else min(timeout, max(0.0, deadline - now))
        try:
            func, args = self._queue.get(timeout=wait) if wait > 0 else self._queue.get_nowait()
        except queue.Empty:
            return False
        func(*args)
        return True

    @property
    def stop_requested(self) -> bool:
        """Whether ``stop`` was asked for."""
        return not self._running

    def stop(self) -> None:
        """Ask ``run`` to return (any thread, signal handlers included): it wakes at once."""
        self._running = False
        self._queue.put((_nothing, ()))

    def run(self) -> bool:
        """Fire timers and run queued callbacks on this thread until ``stop``, then the shutdown
        hooks.  False if a callback raised: the traceback is logged once and the node stops as
        if asked to (its hooks still run)."""
        ok = True
        # this loop turns at the fastest timer's rate (the simulator's 62.5 Hz): names bound once,
        # no generator per turn (the time source is set before the node runs)
        timers, get, clock, empty, fire_due = self._timers, self._queue.get, self.clock, queue.Empty, self.fire_due
        sim, log = self._sim, self.log
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
                    sim.say_if_waiting(log)
                try:
                    func, args = get(timeout=sim.timeout(wake) if sim is not None else max(0.0, wake - clock()))
                except empty:
                    continue
                func(*args)
        except Exception:  # node code: a defect, reported once; stop cleanly and let respawn apply
            log.exception("stopping after an error in node code")
            ok = False
        self.shutdown()
        return ok

    def on_shutdown(self, callback: Callable[[], None]) -> None:
        """Run ``callback()`` on the node's thread when it stops (``shutdown``)."""
        self._on_shutdown.append(callback)

    def shutdown(self) -> None:
        """Run the shutdown hooks once, each even if an earlier one raised."""
        hooks, self._on_shutdown = self._on_shutdown, []
        self._running = False
        for callback in hooks:
            try:
                callback()
            except Exception:  # one failing hook must not keep the next (e.g. the stop command) from running
                self.log.exception("shutdown hook %s failed", getattr(callback, "__qualname__", callback))


def _nothing() -> None:
    """A queue item that only wakes the node's thread (it then fires what is due)."""
