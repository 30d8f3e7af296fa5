"""``turtlectl.Subscription``: messages on a topic, as ``Client.subscribe`` returns them."""

from __future__ import annotations

import queue
import time
from collections.abc import Callable, Iterator

import zenoh

from turtlectl.messages import Message
from turtlectl.runtime.client import presence
from turtlectl.runtime.client.errors import Failed
from turtlectl.runtime.client.samples import Received, decode_sample, learn
from turtlectl.runtime.client.typebook import TypeBook
from turtlectl.runtime.handles import Declaration


class Subscription(Declaration):
    """Messages on a topic: iterate over it (``for status in sub``; each waits for the next), or
    give ``subscribe`` a callback (called on Zenoh's thread).  ``undeclare()`` ends it."""

    def __init__(
        self,
        owner: list[Declaration],
        session: zenoh.Session,
        key: str,
        callback: Callable[[Message], None] | None,
        book: TypeBook,
    ):
        super().__init__(owner, "subscription", key)
        self._inbox: queue.SimpleQueue[Received | None] = queue.SimpleQueue()
        self._book = book
        #: payloads that did not decode (skipped), and why the last one did not
        self.skipped = 0
        self.last_problem = ""

        def on_sample(sample: zenoh.Sample) -> None:  # Zenoh's thread
            got = decode_sample(str(sample.key_expr), sample.payload.to_bytes(), str(sample.encoding))
            if callback is None:
                self._inbox.put(got)
            elif got.message is not None and self.active:
                callback(got.message)
            elif got.message is None:
                self._skip(got)

        # on Zenoh's own thread (indirect=False): a Python thread per subscription (zenoh-python's
        # default) is not a daemon, and kept a script that never undeclared it from ending
        self.add(presence.subscriber(session, key, zenoh.handlers.Callback(on_sample, indirect=False)))

    def undeclare(self) -> None:
        """End it: no more messages; an iteration over it ends."""
        if self.active:
            super().undeclare()
            self._inbox.put(None)

    def next(self, timeout: float | None = None) -> Message:
        """The next message (a type not known yet is learnt from the nodes that use it; a
        payload that does not decode is skipped and counted in ``skipped``, its reason in
        ``last_problem``); Failed after ``timeout`` s."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            try:
                got = self._inbox.get(timeout=None if deadline is None else max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                raise Failed(f"no message within {timeout:g} s") from None
            if got is None:
                raise StopIteration
            got = learn(got, self._book)
            if got.message is not None:
                return got.message
            self._skip(got)

    def _skip(self, got: Received) -> None:
        self.skipped += 1
        self.last_problem = got.problem or f"a {got.type_name or 'message'} payload that no node describes"

    def __iter__(self) -> Iterator[Message]:
        while True:
            try:
                yield self.next()
            except StopIteration:
                return


__all__ = ["Subscription"]
