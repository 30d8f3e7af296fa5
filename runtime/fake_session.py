"""The in-memory session under ``FakeNode`` (runtime.fake): what a node declares on it
(publishers, subscribers, queryables, liveliness tokens) is kept in lists, and a test's
``deliver``, ``query`` and ``token`` reach the matching ones at once, on the test's thread.
Samples and queries carry what node code reads of zenoh's (``key_expr``, ``payload`` as real
``ZBytes``, ``encoding``, ``attachment``); nothing else of Zenoh runs."""

from __future__ import annotations

import collections
from collections.abc import Callable
from types import SimpleNamespace
from typing import Any

import zenoh

from turtlectl.messages import Message, decode_any, encode
from turtlectl.runtime.entities import sample_encoding

__all__ = ["JSON", "FakeSession", "RawReplies"]

JSON = zenoh.Encoding.APPLICATION_JSON


def _matches(a: str, b: str) -> bool:
    return zenoh.KeyExpr(a).intersects(zenoh.KeyExpr(b))


def _sample(key: str, data: bytes, encoding: Any = None, kind: Any = zenoh.SampleKind.PUT) -> SimpleNamespace:
    """What a subscriber callback reads of a ``zenoh.Sample`` (the payload is a real ``ZBytes``)."""
    return SimpleNamespace(key_expr=key, payload=zenoh.ZBytes(data), encoding=encoding, kind=kind)


class _Query:
    """What a queryable callback reads and calls of a ``zenoh.Query``: replies are kept, an
    error one (``reply_err``) as any other (its payload is an ``ErrorReply``)."""

    def __init__(
        self, key: str, data: bytes | None, encoding: Any, replies: RawReplies, attachment: bytes | None = None
    ):
        self.key_expr, self.encoding, self.replies = key, encoding, replies
        self.payload = None if data is None else zenoh.ZBytes(data)
        self.attachment = None if attachment is None else zenoh.ZBytes(attachment)
        self.dropped = False

    def reply(self, key: str, payload: bytes, encoding: Any = None) -> None:
        self.replies.append((bytes(payload), encoding))

    def reply_err(self, payload: bytes, encoding: Any = None) -> None:
        self.replies.append((bytes(payload), encoding))

    def drop(self) -> None:
        self.dropped = True
        self.replies.ended = True


class RawReplies(list[tuple[bytes, Any]]):
    """One query's raw replies, as they come; ``ended``: a queryable ended the call (its final reply)."""

    ended = False


class _Entity:
    """A declared publisher, subscriber, queryable or token: ``undeclare`` takes it out."""

    def __init__(self, registry: list[Any], key: str, target: Any = None):
        self.key = key
        self.target = target
        self._registry = registry
        registry.append(self)

    def undeclare(self) -> None:
        if self in self._registry:
            self._registry.remove(self)


class _Ring(_Entity):
    """A subscriber with a ring channel (``zenoh.handlers.RingChannel(n)``): it keeps the samples
    for ``try_recv``, oldest first (all of them: a fake clock's test reads when it likes)."""

    def __init__(self, registry: list[Any], key: str):
        super().__init__(registry, key, self._keep)
        self._kept: collections.deque[Any] = collections.deque()

    def _keep(self, sample: Any) -> None:
        self._kept.append(sample)

    def try_recv(self) -> Any:
        return self._kept.popleft() if self._kept else None


class _Publisher(_Entity):
    def __init__(self, session: FakeSession, key: str, encoding: Any):
        super().__init__(session.publishers, key)
        self._session = session
        self.encoding = encoding

    def put(self, payload: bytes) -> None:
        self._session.put(self.key, bytes(payload), self.encoding)


class FakeSession:
    """An in-memory stand-in for what ``Node`` and its entities use of a ``zenoh.Session``.
    A ``put`` is recorded and delivered to the matching subscribers of this session (as Zenoh
    delivers locally); a ``get`` is answered by ``answers`` (``FakeNode.answer``)."""

    def __init__(self) -> None:
        self.published: list[tuple[str, bytes]] = []
        self.publishers: list[_Publisher] = []
        self.subscribers: list[_Entity] = []
        self.queryables: list[_Entity] = []
        self.tokens: list[_Entity] = []
        self.liveliness_subscribers: list[_Entity] = []
        self.answers: dict[str, Callable[[Message], list[Message]]] = {}
        self.info = SimpleNamespace(routers_zid=list)  # no router: ``Node.claim`` has nobody to ask

    # what the node declares
    def declare_publisher(self, key: str, encoding: Any = None) -> _Publisher:
        return _Publisher(self, key, encoding)

    def declare_subscriber(self, key: str, callback: Callable[[Any], None] | zenoh.handlers.RingChannel) -> _Entity:
        if isinstance(callback, zenoh.handlers.RingChannel):
            return _Ring(self.subscribers, key)
        return _Entity(self.subscribers, key, callback)

    def declare_queryable(self, key: str, callback: Callable[[Any], None]) -> _Entity:
        return _Entity(self.queryables, key, callback)

    def liveliness(self) -> SimpleNamespace:
        return SimpleNamespace(
            declare_token=lambda key: _Entity(self.tokens, key),
            declare_subscriber=lambda key, callback, **_: _Entity(self.liveliness_subscribers, key, callback),
            get=lambda key, handler=None, **_: None,  # a liveliness query: no other process, no reply
        )

    def get(self, key: str, handler: zenoh.handlers.Callback, payload: bytes | None = None, **_: Any) -> None:
        """The node queries ``key``: what ``answers`` holds for it replies, then it is done."""
        for served, answer in list(self.answers.items()):
            if _matches(served, key):
                for reply in answer(decode_any(payload if payload is not None else b"\x80")):
                    handler.callback(SimpleNamespace(ok=_sample(served, encode(reply), sample_encoding(type(reply)))))
        handler.drop()

    # what comes to the node
    def put(self, key: str, data: bytes, encoding: Any = None) -> None:
        """A sample on ``key``: recorded if the node published it, delivered to every match."""
        self.published.append((key, data))
        self.deliver(key, data, encoding)

    def deliver(self, key: str, data: bytes, encoding: Any = None) -> None:
        for sub in list(self.subscribers):
            if _matches(sub.key, key):
                sub.target(_sample(key, data, encoding))

    def query(self, key: str, data: bytes | None, encoding: Any = None, attachment: bytes | None = None) -> RawReplies:
        """Query every matching queryable; their replies, as they come (the list grows)."""
        replies = RawReplies()
        for queryable in list(self.queryables):
            if _matches(queryable.key, key):
                queryable.target(_Query(key, data, encoding, replies, attachment))
        return replies

    def token(self, key: str, alive: bool) -> None:
        kind = zenoh.SampleKind.PUT if alive else zenoh.SampleKind.DELETE
        for sub in list(self.liveliness_subscribers):
            if _matches(sub.key, key):
                sub.target(_sample(key, b"", None, kind))
