"""The node's declaration kinds, each a ``Kind`` and a function over the node's core
(runtime.core.NodeCore.declare): ``Node``'s methods call them for node code, and the runtime's own
declarations (runtime.own_services, runtime.simtime) call them with ``own=True``.  Each returns a
handle with ``undeclare()`` (runtime.handles).

Zenoh delivers samples and queries on its own threads: the callbacks here only queue the work
for the node's thread (``NodeCore.enqueue``), where a callback of a declaration undeclared
meanwhile does not run."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

import zenoh

from turtlectl.messages import Message, decode
from turtlectl.runtime.core import Kind, NodeCore
from turtlectl.runtime.entities import RING, Latest, Publisher, Request
from turtlectl.runtime.handles import Declaration

M = TypeVar("M", bound=Message)

PUBLISHER = Kind("publisher", "publish", ("pub",))
SUBSCRIPTION = Kind("subscription", "subscribe", ("sub",))
SERVICE = Kind("service", "serve", ("srv",))
JSON_ANSWER = Kind("JSON answer", "serve", ("srv",), type_name="JSON")
LIVELINESS_WATCH = Kind("liveliness watch", "watch")


def publisher(core: NodeCore, key: str, msg_type: type[M], *, own: bool = False) -> Publisher[M]:
    """A publisher of ``msg_type`` on ``key``, stamping with the core's time."""
    return core.declare(
        PUBLISHER, key, (msg_type,), lambda d: Publisher(core.session, d.key, msg_type, d, core.now_ns), own=own
    )


def subscription(
    core: NodeCore, key: str, msg_type: type[M], callback: Callable[[M], None], *, own: bool = False
) -> Declaration:
    """``callback(msg)`` on the node's thread for each valid ``msg_type`` on ``key`` (a malformed
    payload: ``NodeCore.reject``)."""

    def build(declared: Declaration) -> Declaration:
        resolved, enqueue = declared.key, core.enqueue

        def on_sample(sample: zenoh.Sample) -> None:  # Zenoh thread: queue only
            enqueue(_deliver, core, resolved, msg_type, sample.payload.to_bytes(), callback, declared)

        declared.add(core.session.declare_subscriber(resolved, on_sample))
        return declared

    return core.declare(SUBSCRIPTION, key, (msg_type,), build, own=own)


def latest(core: NodeCore, key: str, msg_type: type[M], keep: int = RING, follow: bool = False) -> Latest[M]:
    """The newest ``msg_type`` on ``key``, read at the node's pace (runtime.entities.Latest)."""
    return core.declare(SUBSCRIPTION, key, (msg_type,), lambda d: Latest(core, d.key, msg_type, d, keep, follow))


def service(
    core: NodeCore,
    key: str,
    request_type: type[M],
    response_type: type[Message],
    handler: Callable[[Request[M]], None],
    *,
    own: bool = False,
) -> Declaration:
    """``handler(request)`` on the node's thread for each query on ``key`` (a malformed request:
    rejected and answered with an error; one queued before the service was undeclared: answered
    "no longer served")."""

    def build(declared: Declaration) -> Declaration:
        resolved, enqueue = declared.key, core.enqueue

        def on_query(query: zenoh.Query) -> None:  # Zenoh thread: queue only
            enqueue(_handle_query, core, resolved, request_type, query, handler, declared)

        declared.add(core.session.declare_queryable(resolved, on_query))
        return declared

    return core.declare(SERVICE, key, (request_type, response_type), build, own=own)


def json_answer(core: NodeCore, key: str, document: bytes | Callable[[], bytes], *, own: bool = False) -> Declaration:
    """Every query on ``key`` answered with a JSON ``document`` (or what ``document()`` returns
    then), right on the Zenoh thread."""

    def build(declared: Declaration) -> Declaration:
        resolved = declared.key

        def on_query(query: zenoh.Query) -> None:
            body = document() if callable(document) else document
            query.reply(resolved, body, encoding=zenoh.Encoding.APPLICATION_JSON)

        declared.add(core.session.declare_queryable(resolved, on_query))
        return declared

    return core.declare(JSON_ANSWER, key, (), build, own=own)


def liveliness_watch(core: NodeCore, key_expr: str, callback: Callable[[str, bool], None]) -> Declaration:
    """``callback(key, alive)`` on the node's thread when a token matching ``key_expr`` appears
    or vanishes."""

    def build(declared: Declaration) -> Declaration:
        def live(key: str, alive: bool) -> None:
            if declared.active:
                callback(key, alive)

        def on_sample(sample: zenoh.Sample) -> None:  # Zenoh thread: queue only
            core.enqueue(live, str(sample.key_expr), sample.kind == zenoh.SampleKind.PUT)

        declared.add(core.session.liveliness().declare_subscriber(declared.key, on_sample))
        return declared

    return core.declare(LIVELINESS_WATCH, key_expr, (), build)


def _deliver(
    core: NodeCore, key: str, msg_type: type[M], payload: bytes, callback: Callable[[M], None], declared: Declaration
) -> None:
    if not declared.active:  # queued before it was undeclared
        return
    try:
        msg = decode(payload, msg_type)
    except ValueError as exc:
        core.reject(key, str(exc))
        return
    callback(msg)


def _handle_query(
    core: NodeCore,
    key: str,
    request_type: type[M],
    query: zenoh.Query,
    handler: Callable[[Request[M]], None],
    declared: Declaration,
) -> None:
    if not declared.active:  # queued before the service was undeclared
        Request(key, query, None).fail(f"{key} is no longer served by {core.name}")
        return
    # no payload at all is an empty map: `reset` and `navigate_to/cancel` need no fields
    payload = query.payload.to_bytes() if query.payload is not None else b"\x80"
    try:
        body = decode(payload, request_type)
    except ValueError as exc:
        core.reject(key, str(exc))
        Request(key, query, None).fail(str(exc))
        return
    handler(Request(key, query, body))
