"""Service calls of the command-line tools: any queryable, goals with feedback, simple Acks.

Nothing here prints; functions return data or raise CliError.
"""

from __future__ import annotations

import os
import queue
import secrets
import time
from collections.abc import Callable, Iterator

import msgspec
import zenoh

from cli.client import check_key, client_session
from cli.errors import CliError, ExitCode
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
from messages.keys import CLIENT_TOKEN_PREFIX, NAVIGATE_TO, WORLD_KEY
from sim.world import World


class NoAnswer(CliError):
    """The call's time ran out (the service may have been answering: feedback)."""


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
        raise NoAnswer(ExitCode.FAILED, f"{key} did not answer within {timeout:g} s")


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
        raise NoAnswer(ExitCode.FAILED, f"{key} did not answer within {timeout:g} s")
    raise CliError(ExitCode.FAILED, f"{key} failed: {payload.decode('utf-8', 'replace') or 'unknown error'}")


NO_LIMIT = 24 * 3600.0  # s: wait for the navigator's own goal_timeout


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
        try:
            for message in replies(session, NAVIGATE_TO, request, timeout):
                if isinstance(message, NavigateToFeedback) and on_feedback is not None:
                    on_feedback(message)
                elif isinstance(message, NavigateToResponse):
                    elapsed = time.monotonic() - started
                    token.undeclare()
                    return message, elapsed
        except NoAnswer:
            raise CliError(
                ExitCode.FAILED, f"the goal did not end within --timeout {timeout:g} s; the navigator cancels it"
            ) from None
    raise CliError(ExitCode.FAILED, "the navigator stopped answering before the goal ended (did it exit?)")



def simple_call(connect: str, key: str, request: Message, everyone: bool = False, timeout: float = 5.0) -> list[Ack]:
    """Call a simple service (Ack answers); with ``everyone``, collect every server's answer."""
    with client_session(connect) as session:
        return [m for m in replies(session, key, request, timeout, everyone) if isinstance(m, Ack)]


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
