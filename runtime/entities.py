"""What a node's declarations give it: a ``Publisher``, a ``Latest`` value, a ``Request``
being served, a ``Timer`` (``runtime.node.Node`` makes them; their threading is that module's
docstring).  Each can be undeclared (``runtime.handles``)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Generic, TypeVar

import zenoh

from turtlectl.messages import ErrorReply, Message, decode, encode, encoding_for
from turtlectl.messages.stamps import with_stamp
from turtlectl.runtime.handles import Declaration

if TYPE_CHECKING:
    from turtlectl.runtime.core import NodeCore

M = TypeVar("M", bound=Message)

_ENCODINGS: dict[type[Message], zenoh.Encoding] = {}
#: samples a ``Latest`` keeps in Zenoh between two reads (a 62.5 Hz pose for 1 s)
RING = 64


def sample_encoding(msg_type: type[Message]) -> zenoh.Encoding:
    """The sample encoding naming ``msg_type`` (made once per type)."""
    encoding = _ENCODINGS.get(msg_type)
    if encoding is None:
        encoding = _ENCODINGS[msg_type] = zenoh.Encoding(encoding_for(msg_type))
    return encoding


class Publisher(Generic[M]):
    """Publishes messages of one type on one key, filling in ``stamp`` and ``seq`` (a type that
    has them: a user's type need not)."""

    def __init__(
        self,
        session: zenoh.Session,
        key: str,
        msg_type: type[M],
        declared: Declaration,
        now_ns: Callable[[], int] = time.time_ns,
    ):
        self.key = key
        self._now_ns = now_ns  # the node's time (ns): the wall clock, or the simulated one
        self._pub = session.declare_publisher(key, encoding=sample_encoding(msg_type))
        self._seq = 0
        self._declaration = declared  # the publisher and its graph token
        declared.add(self._pub)

    def publish(self, msg: M) -> M:
        """Stamp ``msg`` with the node's time (ns: the wall clock, or the simulated one with
        ``use_sim_time``) and the next sequence number, then send it."""
        stamped = with_stamp(msg, self._now_ns, self._seq)
        self._seq += 1
        self._pub.put(encode(stamped))
        return stamped

    def undeclare(self) -> None:
        """Stop publishing on the key (and leave the graph).  Idempotent."""
        self._declaration.undeclare()


class Latest(Generic[M]):
    """The newest valid message of one type on one key, read when the node wants it.

    Zenoh keeps the samples in Rust (a ring channel of ``RING``): Python is not woken for them,
    so a node that needs a 62.5 Hz pose only at its own 10 Hz tick is woken 10 times a second,
    not 62.5.  ``get()`` takes what came since the last read, oldest first: each malformed
    payload is counted and logged there, as ``Node.subscribe`` does (a newer valid sample
    hides none), and the newest valid message is kept (only a reader slower than RING samples
    loses the oldest unread, to the ring).  ``get()`` returns the newest valid message, or
    None before the first.

    ``each(callback)`` also calls ``callback`` on the node thread for every valid message (a
    callback subscriber beside the ring).  With ``follow`` that subscriber is declared at once,
    so a node that will call ``each`` gets its first message without waiting for a new
    subscriber to reach the publisher (the navigator's first control step of a goal); it then
    wakes Python per sample, doing nothing while no callback is set."""

    def __init__(
        self,
        core: NodeCore,
        key: str,
        msg_type: type[M],
        declared: Declaration,
        keep: int = RING,
        follow: bool = False,
    ):
        self.key = key
        self._core = core
        self._type = msg_type
        self._value: M | None = None
        self._callback: Callable[[M], None] | None = None
        self._generation = 0  # which callback a queued message was received for
        self._ring = core.session.declare_subscriber(key, zenoh.handlers.RingChannel(keep))
        self._each: zenoh.Subscriber | None = None  # the callback subscriber, once needed
        self._declaration = declared  # the subscribers and its graph token
        declared.add(self._ring)
        if follow:
            self._each = core.session.declare_subscriber(key, self._on_sample)
            declared.add(self._each)

    def _on_sample(self, sample: zenoh.Sample) -> None:  # Zenoh thread: decode and queue, while each() is set
        if self._callback is None:
            return
        try:
            msg = decode(sample.payload.to_bytes(), self._type)
        except ValueError as exc:
            self._core.enqueue(self._core.reject, self.key, str(exc))
            return
        self._value = msg  # one reference swapped: the node thread reads whole messages only
        generation = self._generation  # read before the callback: a change in between drops msg
        if self._callback is not None:
            self._core.enqueue(self._dispatch, msg, generation)

    def get(self) -> M | None:
        """The newest valid message received so far (None: none yet)."""
        self.received()
        return self._value

    def received(self) -> list[M]:
        """Every valid message that came since the last read (``get`` or this), oldest first
        (at most the ring's ``keep``): a node that needs each one, but only at its own pace (the
        status monitor sums the distance between poses at its tick)."""
        if not self._declaration.active:
            return []
        got: list[M] = []
        while (sample := self._ring.try_recv()) is not None:
            try:
                got.append(decode(sample.payload.to_bytes(), self._type))
            except ValueError as exc:
                self._core.reject(self.key, str(exc))
        if got:
            self._value = got[-1]
        return got

    def each(self, callback: Callable[[M], None] | None) -> None:
        """While ``callback`` is set, also call it on the node thread for every valid message,
        as ``Node.subscribe`` does (the navigator needs every pose only while a goal runs);
        None stops it; messages received before a call (still queued) reach no callback set by
        it (setting the same callback again changes nothing: what is queued still reaches it).
        ``get()`` works either way."""
        if callback == self._callback:  # a bound method is a new object each time: equal, not same
            return
        self._generation += 1
        self._callback = callback
        if callback is not None and self._each is None and self._declaration.active:
            self._each = self._core.session.declare_subscriber(self.key, self._on_sample)
            self._declaration.add(self._each)

    def _dispatch(self, msg: M, generation: int) -> None:
        if self._callback is not None and generation == self._generation:
            self._callback(msg)

    def undeclare(self) -> None:
        """Stop receiving (and leave the graph); ``get()`` keeps the last message.  Idempotent."""
        self._callback = None
        self._generation += 1  # what is queued reaches no callback
        self._declaration.undeclare()


class Request(Generic[M]):
    """A service request being handled; reply once, now or later, with ``respond``."""

    def __init__(self, key: str, query: zenoh.Query, body: M):
        self.body = body
        self._key = key
        self._query = query
        self.done = False

    @property
    def attachment(self) -> bytes | None:
        """The query's attachment, if it has one (a goal's caller id: runtime.goals)."""
        attachment = getattr(self._query, "attachment", None)
        return None if attachment is None else attachment.to_bytes()

    def respond(self, response: Message, final: bool = True) -> None:
        """Send ``response`` to the caller (its encoding names its own type, feedback
        included); with final=True the call ends."""
        if self.done:
            return
        self._query.reply(self._key, encode(response), encoding=sample_encoding(type(response)))
        if final:
            self.done = True
            self._query.drop()

    def fail(self, error: str) -> None:
        """End the call with an error reply (the client reports it as bad input)."""
        if self.done:
            return
        self.done = True
        self._query.reply_err(encode(ErrorReply(error=error)), encoding=sample_encoding(ErrorReply))
        self._query.drop()


class Timer:
    """A periodic callback on an absolute grid (tick k due at ``start + k * period``); a
    paused timer is not due at all, so it does not wake the node.  ``clock`` (s) is the node's;
    ``owner``: the list of timers the node fires, which it joins (and leaves when undeclared)."""

    def __init__(
        self,
        period: float,
        callback: Callable[[], None],
        start: float,
        clock: Callable[[], float] = time.monotonic,
        owner: list[Timer] | None = None,
    ):
        self.period = period
        self.callback = callback
        self.start = start
        self.ticks = 1
        self.deadline = start + period
        self.active = True
        self.undeclared = False
        self._owner = owner
        self._clock = clock  # s: read when ``retime``/``resume`` are not told ``now`` (the node's)
        if owner is not None:
            owner.append(self)

    def retime(self, period: float, now: float | None = None) -> None:
        """Tick every ``period`` s from now on (a grid starting ``now``; the next tick is one
        new period away)."""
        now = self._clock() if now is None else now
        self.period, self.start, self.ticks = period, now, 1
        self.deadline = now + period

    def advance(self, now: float) -> None:
        """Next deadline on the absolute grid; missed ticks are skipped, not bunched."""
        self.ticks = max(self.ticks + 1, int((now - self.start) / self.period) + 1)
        self.deadline = self.start + self.ticks * self.period

    def pause(self) -> None:
        """No more ticks until ``resume``."""
        self.active = False

    def undeclare(self) -> None:
        """No more ticks, ever (``resume`` does nothing after this).  Idempotent."""
        self.active = False
        self.undeclared = True
        if self._owner is not None and self in self._owner:
            self._owner.remove(self)

    def resume(self, now: float | None = None) -> None:
        """Tick again, on the same grid: the next tick is the one due after ``now`` (the
        ticks missed while paused are skipped, as a stalled timer's are)."""
        if self.active or self.undeclared:
            return
        self.active = True
        now = self._clock() if now is None else now
        if self.deadline <= now:
            self.ticks = int((now - self.start) / self.period) + 1
            self.deadline = self.start + self.ticks * self.period
