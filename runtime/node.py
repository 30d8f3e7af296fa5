"""The node API every turtlectl process uses: publishers, subscriptions, services,
timers, liveliness and claims, on a single logic thread (the process around it is
``runtime.lifecycle``).

A node is written as a class whose constructor takes a ``Node`` and declares
what it needs through it::

    class Talker:
        def __init__(self, node: Node[TalkerParams]):
            self.pub = node.publisher("chatter", Twist)
            node.timer(0.1, self.tick)

    if __name__ == "__main__":
        run_main(Talker, TalkerParams)  # runtime.lifecycle: runs the node, then exits with its code

Threading: Zenoh delivers samples and queries on its own threads; the runtime
only queues them there.  Every callback, timer and handler of the node runs on
the main thread, one at a time, so node code needs no locks.  A node that needs only
the newest message at its own rate reads it with ``node.latest(key, type).get()``
at its tick: each sample is decoded and kept where Zenoh delivers it, and the node's
thread is not woken for it.

Timers run on an absolute-deadline schedule (tick k is due at start + k*period),
so the period does not drift with the time the callbacks take, on the node's ``clock``
(``time.monotonic``; ``runtime.fake.FakeNode`` runs a node class on a fake one, without Zenoh).

Every declaration returns a handle with ``undeclare()`` (``runtime.handles``): the
entity and its graph token go, and its callbacks are silenced at once, even one
already queued.
"""

from __future__ import annotations

import logging
import os
import queue
import time
from collections.abc import Callable
from typing import Any, Generic, TypeVar

import msgspec
import zenoh

from turtlectl.messages import (
    Message,
    decode,
)
from turtlectl.messages.codec import type_name
from turtlectl.messages.keys import (
    EntityInfo,
    entity_token,
    namespace_of,
    resolve,
    turtle_of,
)
from turtlectl.messages.world import Limits, World
from turtlectl.runtime.calls import NodeCalls
from turtlectl.runtime.claims import entities_on_router
from turtlectl.runtime.client.errors import CannotStart
from turtlectl.runtime.config import Claim, Interface, NodeConfig
from turtlectl.runtime.entities import RING, Latest, Publisher, Request, Timer
from turtlectl.runtime.handles import Declaration
from turtlectl.runtime.interface import check
from turtlectl.runtime.loop import NodeLoop
from turtlectl.runtime.own_services import OwnServices
from turtlectl.runtime.simtime import SimClock, follow_clock

P = TypeVar("P", bound=msgspec.Struct)
M = TypeVar("M", bound=Message)

__all__ = ["Latest", "Node", "NodeConflict", "Publisher", "Request", "Timer"]  # the entities are runtime.entities'


class NodeConflict(CannotStart):
    """Another running node, ``other`` (pid ``pid``), already does what this one claims to do
    alone (``claim``: the claim's phrase, "serves navigate_to"); exit code 4."""

    def __init__(self, other: str, pid: int, claim: str):
        super().__init__(
            f"{other} (pid {pid}) already {claim}; not starting a second one "
            "(stop it first, or run this one in another --domain)"
        )
        self.other, self.pid, self.claim = other, pid, claim


class Node(NodeLoop, NodeCalls, Generic[P]):
    """A running node, handed to a node class's constructor (``def __init__(self, node)``);
    the runtime makes it, a node's code never does.

    What a node reads: ``name``, ``params`` (its ``Params`` Struct: the launch file's values,
    swapped whole when ``param set`` changes one; read it where it is used), ``world`` and
    ``limits`` (the launch file's), ``log`` (its logger: its lines are prefixed with its name
    and kept in its log file), ``clock()`` (s: monotonic; the simulated time with
    ``use_sim_time``, runtime.simtime; a fake one under ``FakeNode``), ``now_ns()`` (ns since the
    epoch, what its messages are stamped with: the wall clock, or the simulated one) and
    ``interface`` (what it may declare).  What it declares: ``publisher``, ``subscribe``,
    ``latest``, ``serve``, ``call``, ``timer``, ``watch_liveliness`` (each returns a handle
    with ``undeclare()``), and the hooks ``on_params`` and ``on_shutdown``.  Every callback
    runs on the node's one thread."""

    def __init__(
        self,
        config: NodeConfig,
        params: P,
        session: zenoh.Session,
        started_ns: int | None = None,
        *,
        clock: Callable[[], float] = time.monotonic,
    ):
        self.name = config.name
        #: the node's namespace (its full name's first part: ``turtle2`` for ``turtle2/navigator``)
        #: and the turtle it is about (the namespace's, or turtle1 outside one)
        self.namespace = namespace_of(config.name)
        self.turtle = turtle_of(self.namespace)
        self.remaps: dict[str, str] = dict(config.remaps)  # key as written -> key used (its launch file's remap)
        self.clock = clock  # s: what timers run on (``runtime.fake`` gives a fake one)
        self._machine_clock = clock
        self._use_sim_time = config.use_sim_time
        self._time_ns: Callable[[], int] = time.time_ns  # what messages are stamped with
        self._sim: SimClock | None = None  # with use_sim_time: the simulator's clock
        self.kind = config.kind
        self.started_ns = time.time_ns() if started_ns is None else started_ns
        self._connect, self._domain, self._credentials = config.connect, config.domain, config.credentials
        self.params: P = params
        self.interface: Interface | None = None  # the runtime's own declarations below are every node's share
        self.world: World = config.world
        self.limits: Limits = config.limits
        self.session = session
        self.log = logging.getLogger(config.name)
        self._queue: queue.SimpleQueue[tuple[Callable[..., None], tuple[Any, ...]]] = queue.SimpleQueue()
        self._timers: list[Timer] = []
        self._entities: list[Declaration] = []  # what it declared, still declared
        self._bad_payloads: dict[str, int] = {}
        self._running = True
        self._on_shutdown: list[Callable[[], None]] = []
        self._on_params: list[Callable[[P], None]] = []
        self._own = OwnServices(self)  # every node's: its parameters, what it is, its log level, its types
        if config.use_sim_time:
            self._sim = follow_clock(self)
        self.interface = config.interface  # from here on, what the node declares is checked against it

    def now_ns(self) -> int:
        """The node's time in ns since the Unix epoch, what its messages are stamped with: the
        wall clock, or with ``use_sim_time`` the simulated one (0 before the simulator's first
        ``Clock``)."""
        return self._time_ns()

    @property
    def uses_sim_time(self) -> bool:
        """Whether the node was started with ``use_sim_time`` (its launch file entry, or
        ``launch --time-scale``)."""
        return self._use_sim_time

    def use_time(self, now_ns: Callable[[], int]) -> None:
        """Stamp this node's messages with ``now_ns()`` (ns since the epoch) from now on: for a
        node that makes the time itself, as the simulator does (its poses carry its simulated
        time).  Its timers and ``clock()`` are the machine's (they pace it), even with
        ``use_sim_time``: call it before declaring a timer."""
        if self._sim is not None:  # it makes the time: it does not follow it
            self._sim.declared.undeclare()
            self._sim, self.clock = None, self._machine_clock
        self._time_ns = now_ns

    # -- declarations -------------------------------------------------------
    def resolve(self, key: str) -> str:
        """The key this node uses for ``key`` as written (messages.keys.resolve): as written
        outside a namespace; in ``turtle2``, ``turtle1/pose`` is ``turtle2/pose`` and
        ``robot/status`` is ``turtle2/robot/status``; ``/turtles`` is always ``turtles``; then
        the launch file's ``remap`` of the node (``remaps``)."""
        return resolve(key, self.namespace, self.remaps)

    def _announce(self, role: str, msg_type: type[Message] | str, key: str) -> zenoh.LivelinessToken:
        """A liveliness token for the graph (``turtlectl list``): this node's role on ``key``
        with a message type (or a type's name, such as "JSON")."""
        name = msg_type if isinstance(msg_type, str) else type_name(msg_type)
        entity = EntityInfo(node=self.name, pid=os.getpid(), role=role, type_name=name, key=key)
        return self.session.liveliness().declare_token(entity_token(entity))

    def publisher(self, key: str, msg_type: type[M]) -> Publisher[M]:
        """A publisher of ``msg_type`` on ``key`` (``publish``; ``undeclare`` withdraws it)."""
        key = self.resolve(key)
        check(self.name, self.interface, "publish", key)
        self._own.uses(msg_type)
        declared = Declaration(self._entities, "publisher", key)
        pub = Publisher(self.session, key, msg_type, declared, self.now_ns)
        declared.add(self._announce("pub", msg_type, key))
        return pub

    def subscribe(self, key: str, msg_type: type[M], callback: Callable[[M], None]) -> Declaration:
        """Call ``callback(msg)`` on the node thread for each valid ``msg_type`` on ``key``,
        until the returned declaration is undeclared."""
        key = self.resolve(key)
        check(self.name, self.interface, "subscribe", key)
        self._own.uses(msg_type)
        declared = Declaration(self._entities, "subscription", key)
        declared.add(self.session.declare_subscriber(key, self._queuing(key, msg_type, callback, declared)))
        declared.add(self._announce("sub", msg_type, key))
        return declared

    def latest(self, key: str, msg_type: type[M], keep: int = RING, follow: bool = False) -> Latest[M]:
        """Keep the newest ``msg_type`` on ``key`` for the node to read at its own pace
        (``.get()``; every one since the last read: ``.received()``, up to ``keep``), without
        waking the node for each message (see ``Latest``); ``follow``: it will also take every
        message at times (``.each(callback)``), ready from now on."""
        key = self.resolve(key)
        check(self.name, self.interface, "subscribe", key)
        self._own.uses(msg_type)
        declared = Declaration(self._entities, "subscription", key)
        latest = Latest(self, key, msg_type, declared, keep, follow)
        declared.add(self._announce("sub", msg_type, key))
        return latest

    def serve(
        self,
        key: str,
        request_type: type[M],
        response_type: type[Message],
        handler: Callable[[Request[M]], None],
    ) -> Declaration:
        """Serve a queryable; ``handler(request)`` runs on the node thread and responds when it
        likes, until the returned declaration is undeclared."""
        key = self.resolve(key)
        check(self.name, self.interface, "serve", key)
        self._own.uses(request_type)
        self._own.uses(response_type)
        declared = Declaration(self._entities, "service", key)

        def on_query(query: zenoh.Query) -> None:  # Zenoh thread: queue only
            self._queue.put((self._handle_query, (key, request_type, response_type, query, handler, declared)))

        declared.add(self.session.declare_queryable(key, on_query))
        declared.add(self._announce("srv", request_type, key))
        return declared

    def claim(self, claim: Claim) -> None:
        """Make sure no other running node is the ``claim.role`` ("pub", "srv") of ``claim.key``:
        two navigators would both drive the turtle, two simulators both publish its pose.
        Raises NodeConflict naming the other node.  The runtime calls it for each claim of the
        node's kind, before the node declares anything."""
        # No router yet: nothing to ask, nothing known to conflict with (and a router that went
        # away, with the supervisor, would only make the node wait).
        if not self.session.info.routers_zid():
            return
        for other in entities_on_router(self._connect, self._domain, self._credentials):
            if (other.role, other.key) == (claim.role, claim.key) and other.pid != os.getpid():
                raise NodeConflict(other.node, other.pid, claim.phrase(third_person=True))

    def answer_json(self, key: str, document: bytes | Callable[[], bytes]) -> Declaration:
        """Answer every query on ``key`` with a JSON ``document``, or what ``document()``
        returns then (read-only: answered right on the Zenoh thread; a callable must only
        read attributes the node thread swaps whole)."""
        key = self.resolve(key)
        check(self.name, self.interface, "serve", key)

        def on_query(query: zenoh.Query) -> None:
            body = document() if callable(document) else document
            query.reply(key, body, encoding=zenoh.Encoding.APPLICATION_JSON)

        declared = Declaration(self._entities, "JSON answer", key)
        declared.add(self.session.declare_queryable(key, on_query))
        declared.add(self._announce("srv", "JSON", key))
        return declared

    def watch_liveliness(self, key_expr: str, callback: Callable[[str, bool], None]) -> Declaration:
        """Call ``callback(key, alive)`` on the node thread when a matching token appears or
        vanishes, until the returned declaration is undeclared."""
        key_expr = self.resolve(key_expr)
        check(self.name, self.interface, "watch", key_expr)
        declared = Declaration(self._entities, "liveliness watch", key_expr)

        def live(key: str, alive: bool) -> None:
            if declared.active:
                callback(key, alive)

        def on_sample(sample: zenoh.Sample) -> None:  # Zenoh thread: queue only
            self._queue.put((live, (str(sample.key_expr), sample.kind == zenoh.SampleKind.PUT)))

        declared.add(self.session.liveliness().declare_subscriber(key_expr, on_sample))
        return declared

    def timer(self, period: float, callback: Callable[[], None]) -> Timer:
        """Call ``callback()`` every ``period`` s on an absolute schedule (until paused)."""
        timer = Timer(period, callback, self.clock(), clock=self.clock)
        timer._owner = self._timers
        self._timers.append(timer)
        return timer

    def on_params(self, callback: Callable[[P], None]) -> None:
        """Call ``callback(params)`` on the node thread after a parameter changed at run time
        (``self.params`` is already the new Struct): a node that keeps something made from a
        parameter (a timer's period, a table of beam angles) makes it again here.  A node that
        reads ``node.params`` where it uses them needs no hook."""
        self._on_params.append(callback)

    def on_shutdown(self, callback: Callable[[], None]) -> None:
        """Run ``callback()`` on the node thread when the node stops (e.g. to stop the turtle)."""
        self._on_shutdown.append(callback)

    # -- internals ----------------------------------------------------------
    def _post(self, fn: Callable[..., None], *args: Any) -> None:
        """Run ``fn(*args)`` on the node's thread, after what is queued already (from any thread)."""
        self._queue.put((fn, args))

    def _declaration(self, what: str, key: str) -> Declaration:
        """A new declaration (``what`` on ``key``, resolved) among the node's, undeclared with it."""
        return Declaration(self._entities, what, key)

    def _uses(self, msg_type: type[Message]) -> None:
        """The node uses ``msg_type``: its own services describe it (runtime.own_services)."""
        self._own.uses(msg_type)

    def _queuing(
        self, key: str, msg_type: type[M], callback: Callable[[M], None], declared: Declaration
    ) -> Callable[[zenoh.Sample], None]:
        """A Zenoh sample callback that only queues ``callback``'s delivery for the node thread."""

        def on_sample(sample: zenoh.Sample) -> None:  # Zenoh thread: queue only
            self._queue.put((self._deliver, (key, msg_type, sample.payload.to_bytes(), callback, declared)))

        return on_sample

    def _rejected(self, key: str, reason: str) -> None:
        """Count a bad payload; log the first per key and then every 100th."""
        count = self._bad_payloads.get(key, 0) + 1
        self._bad_payloads[key] = count
        if count == 1 or count % 100 == 0:
            self.log.warning("dropped malformed payload #%d on %s: %s", count, key, reason)

    def _deliver(
        self, key: str, msg_type: type[M], payload: bytes, callback: Callable[[M], None], declared: Declaration
    ) -> None:
        if not declared.active:  # queued before it was undeclared
            return
        try:
            msg = decode(payload, msg_type)
        except ValueError as exc:
            self._rejected(key, str(exc))
            return
        callback(msg)

    def _handle_query(
        self,
        key: str,
        request_type: type[M],
        response_type: type[Message],
        query: zenoh.Query,
        handler: Callable[[Request[M]], None],
        declared: Declaration,
    ) -> None:
        if not declared.active:  # queued before the service was undeclared
            Request(key, query, None).fail(f"{key} is no longer served by {self.name}")
            return
        # no payload at all is an empty map: `reset` and `navigate_to/cancel` need no fields
        payload = query.payload.to_bytes() if query.payload is not None else b"\x80"
        try:
            body = decode(payload, request_type)
        except ValueError as exc:
            self._rejected(key, str(exc))
            Request(key, query, None).fail(str(exc))
            return
        handler(Request(key, query, body))
