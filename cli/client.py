"""Client-side logic of the command-line tools: sessions, service calls, subscriptions.

Nothing here prints; functions return data or raise CliError.
"""

from __future__ import annotations

import collections
import contextlib
import math
import os
import queue
import re
import secrets
import time
from collections.abc import Callable, Iterator
from typing import TypeVar

import msgspec
import zenoh

from cli.errors import CliError, ExitCode
from cli.graph import Graph, build_graph
from cli.rates import RateStats, rate_stats
from messages import (
    Ack,
    DecodeError,
    ErrorReply,
    Message,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    decode,
    decode_any,
    encode,
    encoding_for,
    type_from_encoding,
)
from messages.codec import MEDIA_TYPE
from messages.keys import CLIENT_TOKEN_PREFIX, GRAPH, NAVIGATE_TO, WORLD_KEY
from nodes.session import client_config, close_session, default_domain
from sim.world import World

M = TypeVar("M", bound=Message)
OPEN_TIMEOUT = 2.5  # s to reach the router before reporting "nothing to talk to"


ENDPOINT_RE = re.compile(r"^(tcp|udp|tls|quic|ws|unixsock-stream)/\S+$")


def check_endpoint(connect: str) -> str:
    """``connect`` if it looks like a Zenoh endpoint (``tcp/HOST:PORT``), else CliError(BAD_INPUT)."""
    if not ENDPOINT_RE.match(connect):
        raise CliError(ExitCode.BAD_INPUT, f"{connect!r} is not an endpoint: write it as tcp/HOST:PORT")
    return connect


def check_key(text: str) -> str:
    """A topic as typed by a user as a Zenoh key expression: a ROS-style leading '/' is
    dropped; anything Zenoh would refuse is CliError(BAD_INPUT)."""
    key = text[1:] if text.startswith("/") and len(text) > 1 else text
    try:
        return str(zenoh.KeyExpr(key))
    except zenoh.ZError:
        raise CliError(
            ExitCode.BAD_INPUT, f"{text!r} is not a valid key expression (like robot/status or turtle1/*)"
        ) from None


@contextlib.contextmanager
def client_session(connect: str) -> Iterator[zenoh.Session]:
    """A Zenoh client session to the router at ``connect``, closed (bounded) on exit."""
    check_endpoint(connect)
    try:
        session = zenoh.open(client_config(connect, OPEN_TIMEOUT, default_domain()))
    except zenoh.ZError:
        raise CliError(
            ExitCode.UNREACHABLE, f"no turtlectl system at {connect} (is `turtlectl launch` running?)"
        ) from None
    try:
        yield session
    finally:
        close_session(session)


def check_goal_input(x: float, y: float, theta: float) -> NavigateToRequest:
    """The request for a goal, or CliError(BAD_INPUT) if a number is not finite."""
    for name, value in (("x", x), ("y", y), ("theta", theta)):
        if not math.isfinite(value):
            raise CliError(ExitCode.BAD_INPUT, f"{name} must be a finite number, got {value}")
    return NavigateToRequest(x=x, y=y, theta=theta)


class Raw(msgspec.Struct):
    """A reply that is not a turtlectl message (e.g. a node's parameters as JSON)."""

    key: str
    encoding: str
    payload: bytes


def replies(
    session: zenoh.Session, key: str, request: Message | bytes, timeout: float, everyone: bool = False
) -> Iterator[Message | Raw]:
    """Send ``request`` to the queryable(s) at ``key``; yield each reply, decoded, as it arrives.

    All replies are kept (no consolidation), so a service can stream feedback
    before its answer; ``everyone`` asks every matching queryable, not just one.
    Raises CliError: UNREACHABLE if nobody serves ``key``, FAILED if nothing
    answers within ``timeout`` s, BAD_INPUT if the service rejects the request.
    """
    inbox: queue.SimpleQueue[zenoh.Reply | None] = queue.SimpleQueue()
    started = time.monotonic()
    if isinstance(request, bytes):
        payload, encoding = request, zenoh.Encoding.APPLICATION_JSON
    else:
        payload, encoding = encode(request), zenoh.Encoding(encoding_for(type(request)))
    session.get(
        key,
        zenoh.handlers.Callback(inbox.put, lambda: inbox.put(None)),
        payload=payload,
        encoding=encoding,
        consolidation=zenoh.ConsolidationMode.NONE,
        target=zenoh.QueryTarget.ALL if everyone else zenoh.QueryTarget.BEST_MATCHING,
        timeout=timeout,
    )
    answered = False
    while True:
        try:
            reply = inbox.get(timeout=0.1)  # short waits keep Ctrl-C responsive
        except queue.Empty:
            continue
        if reply is None:
            break
        answered = True
        yield _read_reply(reply, key, timeout)
    if not answered:
        if time.monotonic() - started < 0.9 * timeout:
            raise CliError(ExitCode.UNREACHABLE, f"nothing serves {key} (is the node running?)")
        raise CliError(ExitCode.FAILED, f"{key} did not answer within {timeout:g} s")


def call(session: zenoh.Session, key: str, request: Message, response_type: type[M], timeout: float) -> M:
    """The one answer of type ``response_type`` to ``request`` (see ``replies``)."""
    for message in replies(session, key, request, timeout):
        if isinstance(message, response_type):
            return message
    raise CliError(ExitCode.FAILED, f"{key} ended the call without an answer")


def _read_reply(reply: zenoh.Reply, key: str, timeout: float) -> Message | Raw:
    if reply.ok is not None:
        sample = reply.ok
        payload, encoding = sample.payload.to_bytes(), str(sample.encoding)
        if not encoding.startswith(MEDIA_TYPE):
            return Raw(key=str(sample.key_expr), encoding=encoding, payload=payload)
        try:
            return decode_any(payload)
        except DecodeError as exc:
            raise CliError(ExitCode.FAILED, f"{key} sent an unreadable answer: {exc}") from None
    err = reply.err
    payload = err.payload.to_bytes() if err is not None else b""
    if err is not None and type_from_encoding(str(err.encoding)) is ErrorReply:
        raise CliError(ExitCode.BAD_INPUT, f"{key} rejected the request: {decode(payload, ErrorReply).error}")
    # not the service's word but Zenoh's: the query timed out or the route broke
    if payload == b"Timeout":
        raise CliError(ExitCode.FAILED, f"{key} did not answer within {timeout:g} s")
    raise CliError(ExitCode.FAILED, f"{key} failed: {payload.decode('utf-8', 'replace') or 'unknown error'}")


def navigate(
    connect: str,
    goal: NavigateToRequest,
    timeout: float,
    on_feedback: Callable[[NavigateToFeedback], None] | None = None,
) -> tuple[NavigateToResponse, float]:
    """Call navigate_to and wait for the outcome; returns it and the time the client measured, s.

    The call carries a liveliness token of this client: if the client goes away
    (Ctrl-C, kill), the navigator cancels the goal.
    """
    client_id = f"{os.getpid()}-{secrets.token_hex(4)}"
    with client_session(connect) as session:
        token = session.liveliness().declare_token(f"{CLIENT_TOKEN_PREFIX}/{client_id}")
        started = time.monotonic()
        request = msgspec.structs.replace(goal, client=client_id)
        for message in replies(session, NAVIGATE_TO, request, timeout):
            if isinstance(message, NavigateToFeedback) and on_feedback is not None:
                on_feedback(message)
            elif isinstance(message, NavigateToResponse):
                elapsed = time.monotonic() - started
                token.undeclare()
                return message, elapsed
    raise CliError(ExitCode.FAILED, "the navigator stopped answering before the goal ended (did it exit?)")


def simple_call(connect: str, key: str, request: Message, everyone: bool = False, timeout: float = 5.0) -> list[Ack]:
    """Call a simple service (Ack answers); with ``everyone``, collect every server's answer."""
    with client_session(connect) as session:
        return [m for m in replies(session, key, request, timeout, everyone) if isinstance(m, Ack)]


class Received:
    """One sample as echo sees it: the key, the decoded message or why it is not one."""

    def __init__(self, key: str, message: Message | None, problem: str = ""):
        self.key = key
        self.message = message
        self.problem = problem


def decode_sample(key: str, payload: bytes, encoding: str) -> Received:
    """Decode by the type named in the sample's encoding (any tagged message otherwise)."""
    msg_type = type_from_encoding(encoding)
    try:
        message = decode(payload, msg_type) if msg_type is not None else decode_any(payload)
    except DecodeError as exc:
        return Received(key, None, f"{exc} (encoding {encoding!r}, {len(payload)} bytes)")
    return Received(key, message)


@contextlib.contextmanager
def subscription(session: zenoh.Session, key: str) -> Iterator[queue.SimpleQueue[Received]]:
    """Queue of decoded samples on ``key`` (a key expression) for the caller's thread."""
    samples: queue.SimpleQueue[Received] = queue.SimpleQueue()

    def on_sample(sample: zenoh.Sample) -> None:  # Zenoh thread: decode and queue
        samples.put(decode_sample(str(sample.key_expr), sample.payload.to_bytes(), str(sample.encoding)))

    sub = session.declare_subscriber(key, on_sample)
    try:
        yield samples
    finally:
        sub.undeclare()


SILENCE = 3.0  # s without any message before echo tells the user


class Silence:
    """Yielded by ``stream`` once when nothing has arrived for SILENCE seconds."""


def stream(connect: str, topic: str, count: int | None, timeout: float | None) -> Iterator[Received | Silence]:
    """Decoded samples on ``key`` until ``count`` valid messages or ``timeout`` s.

    Yields a ``Silence`` once if nothing at all arrives for SILENCE s.  Raises
    CliError(UNREACHABLE) if ``timeout`` passes without any message.
    """
    key = check_key(topic)
    with client_session(connect) as session, subscription(session, key) as samples:
        started = time.monotonic()
        deadline = None if timeout is None else started + timeout
        received = 0
        warned = False
        while count is None or received < count:
            now = time.monotonic()
            if deadline is not None and now >= deadline:
                if received == 0:
                    raise CliError(ExitCode.UNREACHABLE, f"no message on {key} within {timeout:g} s")
                return
            if not warned and received == 0 and now - started >= SILENCE:
                warned = True
                yield Silence()
            wait = 0.1 if deadline is None else min(0.1, max(0.0, deadline - now))
            try:
                item = samples.get(timeout=wait)  # short waits keep Ctrl-C responsive
            except queue.Empty:
                continue
            if item.message is not None:
                received += 1
            yield item


def graph(connect: str) -> Graph:
    """The live graph: asked of the router's liveliness table now, never cached."""
    with client_session(connect) as session:
        keys = [str(r.ok.key_expr) for r in session.liveliness().get(GRAPH, timeout=2.0) if r.ok is not None]
    return build_graph(keys, time.time_ns())


def measure_rates(
    connect: str, topics: list[str], window: int, duration: float | None
) -> Iterator[list[RateStats]]:
    """Every second, the rate statistics of each topic over its last ``window`` messages;
    ends after ``duration`` s (None: until Ctrl-C)."""
    keys = [check_key(t) for t in topics]
    arrivals = {k: collections.deque(maxlen=window) for k in keys}
    stamps = {k: collections.deque(maxlen=window) for k in keys}
    inbox: queue.SimpleQueue[tuple[str, float, bytes]] = queue.SimpleQueue()
    with client_session(connect) as session:
        subs = [
            session.declare_subscriber(k, lambda s, k=k: inbox.put((k, time.monotonic(), s.payload.to_bytes())))
            for k in keys
        ]
        started = time.monotonic()
        next_report = started + 1.0
        while duration is None or time.monotonic() - started < duration:
            try:
                key, arrived, payload = inbox.get(timeout=0.05)
                arrivals[key].append(arrived)
                try:
                    stamps[key].append(getattr(decode_any(payload), "stamp", 0))
                except DecodeError:
                    pass
            except queue.Empty:
                pass
            if time.monotonic() >= next_report:
                next_report += 1.0
                yield [st for k in keys if (st := rate_stats(k, list(arrivals[k]), list(stamps[k]))) is not None]
        for sub in subs:
            sub.undeclare()
        yield [st for k in keys if (st := rate_stats(k, list(arrivals[k]), list(stamps[k]))) is not None]


def publish(connect: str, topic: str, message: Message, rate: float | None, times: int | None) -> int:
    """Publish ``message`` on ``topic`` ``times`` times (None: until Ctrl-C) at ``rate`` Hz,
    stamping each copy; returns how many were sent."""
    key = check_key(topic)
    sent = 0
    with client_session(connect) as session:
        pub = session.declare_publisher(key, encoding=zenoh.Encoding(encoding_for(type(message))))
        period = 1.0 / rate if rate else 0.0
        start = time.monotonic()
        try:
            while times is None or sent < times:
                if sent:
                    time.sleep(max(0.0, start + sent * period - time.monotonic()))  # absolute schedule
                stamped = message
                if "stamp" in type(message).__struct_fields__:
                    stamped = msgspec.structs.replace(message, stamp=time.time_ns(), seq=sent)
                pub.put(encode(stamped))
                sent += 1
        finally:
            pub.undeclare()
    return sent


def call_service(connect: str, key: str, request: Message | bytes, timeout: float) -> list[Message | Raw]:
    """Every reply of a generic service call (known services typed, others as JSON)."""
    with client_session(connect) as session:
        return list(replies(session, check_key(key), request, timeout))


def world(session: zenoh.Session) -> World:
    """The world as the simulator declares it (the default world if no simulator answers)."""
    for reply in session.get(WORLD_KEY, timeout=2.0):
        if reply.ok is not None:
            try:
                return msgspec.json.decode(reply.ok.payload.to_bytes(), type=World)
            except msgspec.DecodeError:
                break
    return World()
