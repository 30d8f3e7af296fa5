"""A ``Future``: a value that comes later, as rclpy's ``call_async`` and ``send_goal_async`` give.

``Node.call`` and a goal client's ``send`` return one.  A node's futures are resolved on the
node's own thread (Zenoh's threads only queue the replies), so their done-callbacks run there,
one at a time, as every other callback of the node: chain them (``then``,
``add_done_callback``) instead of waiting, which would block the thread that resolves them.
``turtlectl.Client``'s futures are resolved on a thread of their own: a script may wait on
them (``result(timeout)``).

Pure: no Zenoh, no clock.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, Generic, TypeVar

from turtlectl.runtime.client.errors import Failed

__all__ = ["Future", "FutureError"]

T = TypeVar("T")
U = TypeVar("U")


class FutureError(Failed):
    """A future's result asked for when it cannot be had: not done yet on the thread that would
    resolve it (waiting there would never end), or not done within the time given (exit code 1)."""


class Future(Generic[T]):
    """A result that comes later: ``done()``, ``result()``, ``exception()``,
    ``add_done_callback(fn)`` and ``then(fn)``.

    ``resolver``: the thread that will resolve it (a node's: the one that made it), on which
    ``result()`` of a future not done raises ``FutureError`` at once instead of waiting forever;
    None: any thread may wait."""

    def __init__(self, resolver: int | None = None) -> None:
        self._done = threading.Event()
        self._result: Any = None
        self._exception: BaseException | None = None
        self._callbacks: list[Callable[[Future[T]], None]] = []
        self._lock = threading.Lock()
        self._resolver = resolver

    @classmethod
    def of_node(cls) -> Future[T]:
        """A future that the calling thread (a node's) resolves."""
        return cls(threading.get_ident())

    # -- the side that waits ---------------------------------------------------
    def done(self) -> bool:
        """Whether it has a result or an exception."""
        return self._done.is_set()

    def result(self, timeout: float | None = None) -> T:
        """The result (the exception it ended with is raised).  Not done yet: wait up to
        ``timeout`` s (None: as long as it takes) on another thread; on the thread that
        resolves it, ``FutureError`` at once (chain with ``then`` instead)."""
        if not self._done.is_set():
            if self._resolver == threading.get_ident():
                raise FutureError(
                    "result() of a future not done yet, on the node's own thread, which would resolve it: "
                    "chain with then() or add_done_callback() instead"
                )
            if not self._done.wait(timeout):
                raise FutureError(f"no result within {timeout:g} s")
        if self._exception is not None:
            raise self._exception
        return self._result  # type: ignore[no-any-return]

    def exception(self) -> BaseException | None:
        """The exception it ended with (None: a result, or not done yet)."""
        return self._exception

    def add_done_callback(self, fn: Callable[[Future[T]], None]) -> None:
        """Call ``fn(future)`` once it is done, on the thread that resolves it (a node's: the
        node's own); at once, on this thread, if it is done already."""
        with self._lock:
            if not self._done.is_set():
                self._callbacks.append(fn)
                return
        fn(self)

    def then(self, fn: Callable[[T], U | Future[U]]) -> Future[U]:
        """A future of ``fn(result)``, called once this one is done (a future ``fn`` returns is
        followed: its result is the new one's).  An exception (this one's, or raised by ``fn``)
        ends the new future with it, unhandled by ``fn``."""
        chained: Future[U] = Future(self._resolver)

        def step(done: Future[T]) -> None:
            if done._exception is not None:
                chained.set_exception(done._exception)
                return
            try:
                value = fn(done._result)
            except Exception as exc:  # the chain's: the new future carries it
                chained.set_exception(exc)
                return
            if isinstance(value, Future):
                value.add_done_callback(chained._copy)
            else:
                chained.set_result(value)

        self.add_done_callback(step)
        return chained

    # -- the side that resolves ------------------------------------------------
    def set_result(self, value: T) -> bool:
        """Resolve it with ``value`` and run its callbacks here; False if it was done already
        (a future is resolved once)."""
        return self._resolve(value, None)

    def set_exception(self, exc: BaseException) -> bool:
        """End it with ``exc`` (raised by ``result()``); False if it was done already."""
        return self._resolve(None, exc)

    def _copy(self, other: Future[Any]) -> None:
        self._resolve(other._result, other._exception)

    def _resolve(self, value: Any, exc: BaseException | None) -> bool:
        with self._lock:
            if self._done.is_set():
                return False
            self._result, self._exception = value, exc
            self._done.set()
            callbacks, self._callbacks = self._callbacks, []
        for fn in callbacks:
            fn(self)
        return True

    def __repr__(self) -> str:
        state = "pending" if not self.done() else ("failed" if self._exception is not None else "done")
        return f"<Future {state}>"
