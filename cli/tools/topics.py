"""Topics for the command-line tools: echo's stream, hz's rates, pub, and the live graph.

Nothing here prints; functions return data or raise a turtlectl.Error (runtime.client.errors).
"""

from __future__ import annotations

import contextlib
import queue
import time
from collections.abc import Callable, Iterator

import msgspec
import zenoh

from turtlectl.cli.tools.rates import SILENCE, Quiet, Rates, RateStats
from turtlectl.cli.tools.routerwatch import watch
from turtlectl.messages import Message, encode, encoding_for
from turtlectl.messages.codec import TYPES_BY_NAME, type_name
from turtlectl.messages.keys import CMD_VEL, FEEDBACK, LOG, PARAMETER_EVENTS, SERVICES, TOPICS
from turtlectl.messages.stamps import with_stamp
from turtlectl.runtime.client import presence
from turtlectl.runtime.client.errors import Unreachable
from turtlectl.runtime.client.graph import Graph
from turtlectl.runtime.client.samples import Received, decode_sample, learn
from turtlectl.runtime.client.session import (
    base_key,
    check_key,
    client_session,
    domain_hint,
    domain_of,
    live_graph,
    require,
)
from turtlectl.runtime.client.typebook import TypeBook, conflicts

WHILE_A_GOAL_RUNS = (FEEDBACK, CMD_VEL)  # published by the navigator only while a goal runs


@contextlib.contextmanager
def subscription(session: zenoh.Session, key: str) -> Iterator[queue.SimpleQueue[Received]]:
    """Queue of decoded samples on ``key`` (a key expression) for the caller's thread."""
    samples: queue.SimpleQueue[Received] = queue.SimpleQueue()

    def on_sample(sample: zenoh.Sample) -> None:  # Zenoh thread: decode and queue
        samples.put(decode_sample(str(sample.key_expr), sample.payload.to_bytes(), str(sample.encoding)))

    sub = presence.subscriber(session, key, on_sample)
    try:
        yield samples
    finally:
        sub.undeclare()


class Notice:
    """A line for the reader about ``key``, between its messages (``text``)."""

    def __init__(self, key: str, text: str):
        self.key = key
        self.text = text


class Silence(Notice):
    """Yielded once per silence when nothing has arrived on ``key`` for SILENCE seconds
    (from the start, or after messages flowed); ``text`` says why, from the live graph (who
    publishes it, and when)."""


def silence_text(key: str, current: Graph, hint: Callable[[], str], domain: str = "", flowed: bool = False) -> str:
    """Why nothing has arrived on ``key`` yet (or, ``flowed``, for SILENCE s after messages
    did) and what to do, given the live graph as a client in ``domain`` sees it (pure but
    for ``hint()``, the domain hint, asked only when no node runs at all)."""
    expr = zenoh.KeyExpr(key)
    yet = f"for {SILENCE:g} s" if flowed else "yet"
    elsewhere = sorted(
        {
            d
            for d in current.domains
            for t in current.topics
            if t.publishers and t.key.startswith(d + "/") and expr.intersects(zenoh.KeyExpr(t.key[len(d) + 1 :]))
        }
    )
    published = [t for t in current.topics if t.publishers and expr.intersects(zenoh.KeyExpr(t.key))]
    publishers = sorted({p for t in published for p in t.publishers})
    if publishers:
        who = f"{', '.join(publishers)} publish{'es' * (len(publishers) == 1)} it"
        if all(base_key(t.key, domain) in WHILE_A_GOAL_RUNS for t in published):
            return f"nothing published on {key} {yet}: {who} only while a goal runs (start one with `turtlectl goto X Y THETA`)"
        if all(base_key(t.key, domain) == PARAMETER_EVENTS for t in published):
            return (
                f"nothing published on {key} {yet}: {who} only when a parameter changes "
                "(`turtlectl param set NODE NAME VALUE`)"
            )
        if all(base_key(t.key, domain).startswith(f"{LOG}/") for t in published):
            return f"nothing published on {key} {yet}: {who} only when {'it logs' if len(publishers) == 1 else 'they log'} a record (`turtlectl log` shows the recent ones)"
        return (
            f"nothing published on {key} for {SILENCE:g} s although {who}: it may be idle "
            "(it publishes only when it has something to say) or stalled (see its log)"
        )
    if elsewhere:
        which = ", ".join(elsewhere)
        return (
            f"nothing published on {key} here: it is published in domain{'s' * (len(elsewhere) > 1)} {which}: "
            f"add it before the command, `turtlectl --domain {elsewhere[0]} ...` (or use {elsewhere[0]}/{key})"
        )
    if current.nodes:
        return f"nothing published on {key} {yet}: no running node publishes it (`turtlectl list` shows the topics)"
    where = f"in domain {domain}" if domain else "on this router"
    return f"nothing published on {key} {yet}: no turtlectl node runs {where} (is `turtlectl launch` running?){hint()}"


def silence_reason(key: str, current: Graph, connect: str, domain: str, flowed: bool = False) -> str:
    """``silence_text`` as a client of ``connect`` in ``domain`` says it (the domain hint asked
    only when no node runs at all)."""
    return silence_text(key, current, lambda: domain_hint(connect, domain), domain, flowed)


def _silence(session: zenoh.Session, connect: str, key: str, flowed: bool) -> Silence:
    return Silence(key, silence_reason(key, live_graph(session), connect, domain_of(session), flowed))


def stream(
    connect: str, domain: str, topic: str, count: int | None, timeout: float | None, exit_on_loss: bool = False
) -> Iterator[Received | Notice]:
    """Decoded samples on ``key`` until ``count`` valid messages or ``timeout`` s.

    Yields a ``Silence`` saying why once per silence of SILENCE s: nothing arrived yet, or
    messages flowed and stopped.  Raises Unreachable if ``timeout`` passes without any
    message.  A lost router and its return are a Notice each (cli.tools.routerwatch; no
    silence is reported meanwhile); with ``exit_on_loss``, RouterLost (Unreachable) instead.
    """
    key = check_key(topic)
    with client_session(connect, domain) as session, subscription(session, key) as samples:
        book = TypeBook(session)
        warned: set[str] = set()  # the type names whose conflict was said
        started = time.monotonic()
        deadline = None if timeout is None else started + timeout
        received = 0
        quiet = Quiet(started)
        router = watch(session, connect, f"messages on {key}", exit_on_loss)
        while count is None or received < count:
            now = time.monotonic()
            if deadline is not None and now >= deadline:
                if received == 0:
                    raise Unreachable(f"no message on {key} within {timeout:g} s")
                return
            if (line := router.check(now)) is not None:
                yield Notice(key, line)
                if not router.lost:  # a silence counts from the return
                    flowed, quiet = quiet.flowed, Quiet(now)
                    quiet.flowed = flowed
            if not router.lost and quiet.due(now):
                yield _silence(session, connect, key, quiet.flowed)
            wait = 0.1 if deadline is None else min(0.1, max(0.0, deadline - now))
            try:
                item = samples.get(timeout=wait)  # short waits keep Ctrl-C responsive
            except queue.Empty:
                continue
            quiet.heard(time.monotonic())
            unknown = item.unknown
            item = learn(item, book)
            if unknown and book.conflict(unknown) and unknown not in warned:
                warned.add(unknown)
                yield Notice(key, f"warning: {book.conflict(unknown)}; each message is shown by the one it fits")
            if item.message is not None or item.generic is not None:
                received += 1
            yield item


def _stamp(payload: bytes) -> int:
    """The message's ``stamp`` in ns, 0 if it has none or is no message (any type, described or
    not: a msgpack map with a ``stamp``)."""
    try:
        data = msgspec.msgpack.decode(payload)
    except msgspec.DecodeError:
        return 0
    stamp = data.get("stamp", 0) if isinstance(data, dict) else 0
    return stamp if isinstance(stamp, int) and stamp > 0 else 0


def measure_rates(
    connect: str, domain: str, topics: list[str], window: int, duration: float | None, exit_on_loss: bool = False
) -> Iterator[list[RateStats] | Notice]:
    """Every second, the rate statistics of the topics that had messages since the last
    report, each over its last SPAN s (at most ``window`` messages; cli.tools.rates); ends after
    ``duration`` s (None: until Ctrl-C).  A topic silent for SILENCE s, from the start or
    after messages flowed, gets one ``Silence`` per silence saying why (as echo's).  A lost
    router and its return are a Notice each, as echo's (with ``exit_on_loss``, RouterLost)."""
    keys = [check_key(t) for t in topics]
    inbox: queue.SimpleQueue[tuple[str, float, bytes]] = queue.SimpleQueue()
    with client_session(connect, domain) as session:
        subs = [
            presence.subscriber(session, k, lambda s, k=k: inbox.put((k, time.monotonic(), s.payload.to_bytes())))
            for k in keys
        ]
        started = time.monotonic()
        rates = Rates(keys, window, started)
        router = watch(session, connect, f"messages on {', '.join(keys)}", exit_on_loss)
        next_report = started + 1.0
        try:
            while duration is None or time.monotonic() - started < duration:
                try:
                    key, arrived, payload = inbox.get(timeout=0.05)
                    rates.add(key, arrived, _stamp(payload))
                except queue.Empty:
                    pass
                now = time.monotonic()
                if (line := router.check(now)) is not None:
                    yield Notice(", ".join(keys), line)
                    rates.quiet_from(now)
                for key, flowed in [] if router.lost else rates.silences(now):
                    yield _silence(session, connect, key, flowed)
                if now >= next_report:
                    next_report += 1.0
                    yield rates.report(now)
            yield rates.report(time.monotonic())
        finally:
            for sub in subs:
                sub.undeclare()


def publish(connect: str, domain: str, topic: str, message: Message, rate: float | None, times: int | None) -> int:
    """Publish ``message`` on ``topic`` ``times`` times (None: until Ctrl-C) at ``rate`` Hz,
    stamping each copy; returns how many were sent."""
    key = check_key(topic)
    sent = 0
    with client_session(connect, domain) as session:
        require(session, "publish", key)
        pub = presence.publisher(session, key, type_name(type(message)), encoding_for(type(message)))
        period = 1.0 / rate if rate else 0.0
        start = time.monotonic()
        try:
            while times is None or sent < times:
                if sent:
                    time.sleep(max(0.0, start + sent * period - time.monotonic()))  # absolute schedule
                pub.put(encode(with_stamp(message, time.time_ns, sent)))
                sent += 1
        finally:
            pub.undeclare()
    return sent


def learn_type(connect: str, domain: str, key: str, type_name: str | None) -> str | None:
    """Before a message for ``key`` is built from JSON (``pub``, ``call``): a type this process
    does not know (``type_name``, or else the one the live graph says ``key`` carries) is learnt
    from the nodes that use it, so it is validated and encoded as a built-in is.  Returns the
    type's name to build with (``type_name``, or the graph's), None when there is none.  Nothing
    to ask for a known type's full name; a short name is looked up among the built-ins and the
    system's types (BadInput for one several of them have); nothing learnt if no node describes
    it (build says it is unknown)."""
    from turtlectl.cli.tools.build import which_type

    if type_name is not None and "/" in type_name and which_type(type_name, TYPES_BY_NAME) is not None:
        return which_type(type_name, TYPES_BY_NAME)  # a full name known here (a short one may be the system's too)
    if type_name is None and (key in TOPICS or key in SERVICES):
        return None
    try:
        with client_session(connect, domain) as session:
            from_graph = None
            if type_name is None:
                current = live_graph(session)
                from_graph = next((r.type for r in [*current.topics, *current.services] if r.key == key), None)
            learnt = TypeBook(session).learn_all()  # every type in use: a service's answer types too
            if type_name is not None:
                type_name = which_type(type_name, [*TYPES_BY_NAME, *learnt]) or type_name
                return type_name
            if from_graph is not None and from_graph in TYPES_BY_NAME:  # a message type, not "JSON"
                type_name = from_graph
    except Unreachable:
        pass  # no system: build says what it can without one
    return type_name if type_name is None else which_type(type_name, TYPES_BY_NAME) or type_name


def graph(connect: str, domain: str) -> Graph:
    """The live graph: asked of the router's liveliness table now, never cached; with the type
    names its nodes describe differently (``conflicts``)."""
    with client_session(connect, domain) as session:
        current = live_graph(session)
        current.conflicts = conflicts(session)
    if not current.nodes:
        current.hint = domain_hint(connect, domain).removeprefix("; ")
    return current
