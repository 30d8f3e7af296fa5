"""Client-side logic of the command-line tools: sessions, service calls, subscriptions.

Nothing here prints; functions return data or raise CliError.
"""

from __future__ import annotations

import contextlib
import math
import queue
import time
from collections.abc import Iterator

import zenoh

from cli.errors import CliError, ExitCode
from messages import (
    DecodeError,
    ErrorReply,
    Message,
    NavigateToRequest,
    NavigateToResponse,
    decode,
    decode_any,
    encode,
    encoding_for,
    type_from_encoding,
)
from messages.keys import NAVIGATE_TO
from nodes.session import client_config, close_session

OPEN_TIMEOUT = 2.5  # s to reach the router before reporting "nothing to talk to"


@contextlib.contextmanager
def client_session(connect: str) -> Iterator[zenoh.Session]:
    """A Zenoh client session to the router at ``connect``, closed (bounded) on exit."""
    try:
        session = zenoh.open(client_config(connect, OPEN_TIMEOUT))
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


def call(
    session: zenoh.Session, key: str, request: Message, response_type: type[Message], timeout: float
) -> Message:
    """Send ``request`` to the queryable at ``key`` and wait for its final response.

    Raises CliError: UNREACHABLE if nobody serves ``key``, FAILED if it does not
    answer within ``timeout`` s, BAD_INPUT if the service rejects the request.
    """
    replies: queue.SimpleQueue[zenoh.Reply | None] = queue.SimpleQueue()
    started = time.monotonic()
    session.get(
        key,
        zenoh.handlers.Callback(replies.put, lambda: replies.put(None)),
        payload=encode(request),
        encoding=zenoh.Encoding(encoding_for(type(request))),
        timeout=timeout,
    )
    answer: Message | None = None
    while True:
        try:
            reply = replies.get(timeout=0.1)  # short waits keep Ctrl-C responsive
        except queue.Empty:
            continue
        if reply is None:
            break
        answer = _read_reply(reply, key, response_type)
    if answer is None:
        if time.monotonic() - started < 0.9 * timeout:
            raise CliError(ExitCode.UNREACHABLE, f"nothing serves {key} (is the node running?)")
        raise CliError(ExitCode.FAILED, f"{key} did not answer within {timeout:g} s")
    return answer


def _read_reply(reply: zenoh.Reply, key: str, response_type: type[Message]) -> Message:
    if reply.ok is not None:
        try:
            return decode(reply.ok.payload.to_bytes(), response_type)
        except DecodeError as exc:
            raise CliError(ExitCode.FAILED, f"{key} sent an unreadable answer: {exc}") from None
    err = reply.err
    try:
        message = decode(err.payload.to_bytes(), ErrorReply).error if err is not None else "unknown error"
    except DecodeError:
        message = err.payload.to_bytes().decode("utf-8", "replace") if err is not None else "unknown error"
    raise CliError(ExitCode.BAD_INPUT, f"{key} rejected the request: {message}")


def navigate(connect: str, request: NavigateToRequest, timeout: float) -> tuple[NavigateToResponse, float]:
    """Call navigate_to; returns the response and the time the client measured, s."""
    with client_session(connect) as session:
        started = time.monotonic()
        response = call(session, NAVIGATE_TO, request, NavigateToResponse, timeout)
        elapsed = time.monotonic() - started
    assert isinstance(response, NavigateToResponse)  # call() decodes as response_type
    return response, elapsed


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


def stream(connect: str, key: str, count: int | None, timeout: float | None) -> Iterator[Received | Silence]:
    """Decoded samples on ``key`` until ``count`` valid messages or ``timeout`` s.

    Yields a ``Silence`` once if nothing at all arrives for SILENCE s.  Raises
    CliError(UNREACHABLE) if ``timeout`` passes without any message.
    """
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
