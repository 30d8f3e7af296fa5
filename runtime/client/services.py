"""Service calls of the command-line tools: any queryable, goals with feedback, simple Acks.

Nothing here prints; functions return data or raise a TurtlectlError (runtime.client.errors).

The rules every call follows (``goto``, ``cancel``, ``teleport``, ``reset`` and ``call``
alike): replies are handed on as they arrive; an answer that says no (``Ack.ok`` false,
``NavigateToResponse.success`` false) is exit code 1 (a goal refused as invalid: 2, as a
teleport refused there, runtime.client.errors.goal_exit_code); nobody serving the key is exit
code 3, with a hint when systems run in other domains.  A goal (its caller token, its
cancel when given up on) is runtime.client.goals', built on ``replies``.
"""

from __future__ import annotations

import contextlib
import queue
import time
from collections.abc import Callable, Iterator
from typing import Any

import msgspec
import zenoh

from turtlectl.messages import (
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
from turtlectl.messages.codec import MEDIA_TYPE
from turtlectl.messages.keys import NAVIGATE_TO, WORLD_KEY
from turtlectl.messages.world import World
from turtlectl.runtime.client.errors import BadInput, ExitCode, Failed, Unreachable, goal_exit_code
from turtlectl.runtime.client.session import (
    base_key,
    check_key,
    client_session,
    domain_hint,
    require,
    router_lost,
)
from turtlectl.runtime.endpoint import default_domain

CALL_TIMEOUT = 5.0  # s: a service call's default (`call`, Client.call) for services other than a goal's
ZENOH_GRACE = 1.0  # s: Zenoh's own query timeout is ours plus this; our deadline decides


class NoAnswer(Failed):
    """The call's time ran out after ``timeout`` s; ``answered``: the service had sent replies
    (feedback) by then."""

    def __init__(self, message: str, answered: bool = False, timeout: float | None = None):
        super().__init__(message)
        self.answered = answered
        self.timeout = timeout


class NobodyServes(Unreachable):
    """No queryable matches the key: ``what`` went unanswered (``nothing serves KEY``), in
    ``domain`` ("": none said), ``advice`` what to check, ``hint`` where systems run instead
    (from ``session.domain_hint``, starting with "; ")."""

    def __init__(self, what: str, advice: str = "", *, domain: str = "", hint: str = ""):
        where = f" in domain {domain}" if domain else ""
        super().__init__(what + where + (f" ({advice})" if advice else "") + hint)
        self.what, self.advice, self.domain, self.hint = what, advice, domain, hint

    @property
    def said(self) -> str:
        return self.what + (f" in domain {self.domain}" if self.domain else "")

    def located(self, domain: str, hint: str) -> NobodyServes:
        """This error in ``domain``, with ``hint``."""
        return NobodyServes(self.what, self.advice, domain=domain if self.advice else "", hint=hint)


class RouterLost(Unreachable):
    """The client session lost its router ``during`` something ("while waiting for KEY"); the
    router's endpoint ``connect`` when known.  A plain message for a loss said otherwise."""

    def __init__(self, message: str = "", *, during: str = "", connect: str = ""):
        if during:
            at = f" at {connect}" if connect else ""
            message = f"lost the router{at} {during} (did `turtlectl launch` stop?)"
        super().__init__(message)
        self.during, self.connect = during, connect

    @property
    def said(self) -> str:
        return (
            f"lost the router{f' at {self.connect}' if self.connect else ''} {self.during}"
            if self.during
            else self.message
        )

    def located(self, connect: str) -> RouterLost:
        """This error naming the router's endpoint ``connect``."""
        return RouterLost(during=self.during, connect=connect) if self.during else self


class Raw(msgspec.Struct):
    """A reply that is not a turtlectl message (e.g. a node's parameters as JSON)."""

    key: str
    encoding: str
    payload: bytes


@contextlib.contextmanager
def service_session(connect: str, domain: str) -> Iterator[zenoh.Session]:
    """A client session whose "nothing serves" errors say which domains have a system."""
    with client_session(connect, domain) as session, hinted(connect):
        yield session


@contextlib.contextmanager
def hinted(connect: str, domain: str | None = None) -> Iterator[None]:
    """Errors of the calls inside say where: the router's endpoint when it is lost, the domain
    and which domains have a system when nothing serves a key."""
    domain = default_domain() if domain is None else domain
    try:
        yield
    except RouterLost as exc:
        raise exc.located(connect) from None
    except NobodyServes as exc:
        raise exc.located(domain, domain_hint(connect, domain)) from None


ROUTER_LOSS_WAIT = 0.5  # s: how long a query's end may come before the session notices its router is gone


def router_lost_soon(session: zenoh.Session, lasted: float) -> bool:
    """Whether the router went away, given a query that ended without any reply after ``lasted``
    s.  One that ends at once means nobody serves the key; one that ran for a while may have
    ended because the router died, which the session notices a moment later: wait for that."""
    if lasted < 0.05:
        return False
    until = time.monotonic() + ROUTER_LOSS_WAIT
    while not router_lost(session):
        if time.monotonic() >= until:
            return False
        time.sleep(0.02)  # pacing: polling the session's router list under a deadline
    return True


def replies(
    session: zenoh.Session,
    key: str,
    request: Message | bytes,
    timeout: float,
    everyone: bool = False,
    attachment: bytes | None = None,
    goal: bool = False,
    idle: bool = False,
) -> Iterator[Any]:
    """Send ``request`` to the queryable(s) at ``key``; yield each reply, decoded, as it arrives.

    All replies are kept (no consolidation), so a service can stream feedback
    before its answer; ``everyone`` asks every matching queryable, not just one.
    Raises NobodyServes (Unreachable) if nobody serves ``key``, RouterLost
    (Unreachable) if the router goes away, NoAnswer (Failed) when ``timeout`` s pass
    before the replies end, BadInput if the service rejects the request.  ``attachment``:
    bytes the query carries beside the request (a goal's caller id); ``goal``: ``key`` is a goal
    service or its ``/cancel`` (a --secure role's check: runtime.client.session.require); ``idle``:
    also yield None each 0.1 s without a reply (a caller keeping a deadline of its own).
    """
    require(session, "call", key, goal_service=goal)
    inbox: queue.SimpleQueue[zenoh.Reply | None] = queue.SimpleQueue()
    started = time.monotonic()
    deadline = started + timeout
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
        timeout=timeout + ZENOH_GRACE,
        attachment=attachment,
    )
    answered = False
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0.0:
            if answered:
                raise NoAnswer(f"{key} answered but did not finish within {timeout:g} s", True, timeout)
            raise NoAnswer(f"{key} did not answer within {timeout:g} s", timeout=timeout)
        try:
            reply = inbox.get(timeout=min(0.1, remaining))  # short waits keep Ctrl-C responsive
        except queue.Empty:
            if idle:
                yield None
            continue
        if reply is None:
            break
        answered = True
        yield _read_reply(reply, key, timeout)
    if router_lost(session) or (not answered and router_lost_soon(session, time.monotonic() - started)):
        raise RouterLost(during=f"while waiting for {key}")
    if not answered:
        raise NobodyServes(f"nothing serves {key}", "is the node running?")


class Rejected(BadInput):
    """The service refused the request (its ErrorReply); ``reason``: its own words."""

    def __init__(self, key: str, reason: str):
        super().__init__(f"{key} rejected the request: {reason}")
        self.reason = reason


def _read_reply(reply: zenoh.Reply, key: str, timeout: float) -> Message | Raw:
    if reply.ok is not None:
        sample = reply.ok
        payload, encoding = sample.payload.to_bytes(), str(sample.encoding)
        if not encoding.startswith(MEDIA_TYPE):
            return Raw(key=str(sample.key_expr), encoding=encoding, payload=payload)
        try:
            return decode_any(payload)  # by the type tag: whatever the encoding says
        except DecodeError as exc:
            raise Failed(f"{key} sent an unreadable answer: {exc}") from None
    err = reply.err
    payload = err.payload.to_bytes() if err is not None else b""
    if err is not None and type_from_encoding(str(err.encoding)) is ErrorReply:
        raise Rejected(key, decode(payload, ErrorReply).error)
    # not the service's word but Zenoh's: the query timed out or the route broke
    if payload == b"Timeout":
        raise NoAnswer(f"{key} did not answer within {timeout:g} s", timeout=timeout)
    raise Failed(f"{key} failed: {payload.decode('utf-8', 'replace') or 'unknown error'}")


def call_service(
    connect: str,
    domain: str,
    key: str,
    request: Message | bytes,
    timeout: float | None,
    on_feedback: Callable[[NavigateToFeedback], None] | None = None,
) -> Iterator[Message | Raw]:
    """Every reply of a generic service call, as it arrives (known services typed, others as
    JSON).  ``navigate_to`` follows goto's rules (``goals.run_goal``: client token, a timeout or
    Ctrl-C cancels the goal and checks the answer): its feedback goes to ``on_feedback`` as it
    arrives, and only its response is yielded.  ``timeout`` None: the navigator's
    goal_timeout for goals, CALL_TIMEOUT s otherwise."""
    key = check_key(key)
    with service_session(connect, domain) as session:
        if base_key(key, domain) == NAVIGATE_TO and isinstance(request, NavigateToRequest):
            from turtlectl.runtime.client import goals  # which builds on this module

            service = goals.navigate_to(key)
            limit = goals.NO_LIMIT if timeout is None else timeout
            yield goals.run_goal(session, service, request, limit, on_feedback, goals.CLI_LIMIT)
        else:
            yield from replies(session, key, request, CALL_TIMEOUT if timeout is None else timeout)


def reply_code(reply: Message | Raw) -> ExitCode:
    """The exit code a final reply means: 1 for an answer that says no (Ack ok=false), a goal's
    result as ``goal_exit_code`` says (2 for a goal refused as invalid), else 0."""
    if isinstance(reply, Ack) and not reply.ok:
        return ExitCode.FAILED
    if isinstance(reply, NavigateToResponse):
        return goal_exit_code(reply)
    return ExitCode.OK


def world(session: zenoh.Session) -> World:
    """The world as the simulator declares it (the default world if no simulator answers)."""
    for reply in session.get(WORLD_KEY, timeout=2.0):
        if reply.ok is not None:
            try:
                return msgspec.json.decode(reply.ok.payload.to_bytes(), type=World)
            except msgspec.DecodeError:
                break
    return World()
