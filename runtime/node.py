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
import time
from collections.abc import Callable
from typing import Any, Generic, TypeVar

import msgspec
import zenoh

from turtlectl.messages import Message
from turtlectl.messages.keys import namespace_of, turtle_of
from turtlectl.messages.world import Limits, World
from turtlectl.runtime import declarations
from turtlectl.runtime.calls import NodeCalls
from turtlectl.runtime.claims import entities_on_router
from turtlectl.runtime.client.errors import CannotStart
from turtlectl.runtime.config import Claim, Interface, NodeConfig
from turtlectl.runtime.core import NodeCore
from turtlectl.runtime.entities import RING, Latest, Publisher, Request, Timer
from turtlectl.runtime.handles import Declaration
from turtlectl.runtime.own_services import OwnServices
from turtlectl.runtime.simtime import follow_clock

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


class Node(NodeCalls, Generic[P]):
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
    runs on the node's one thread: ``spin`` runs it until ``stop``; a script or test that
    drives a node from its own thread calls ``spin_once`` or ``spin_until`` instead.

    ``core`` is the node's ``runtime.core.NodeCore`` (its queue, timers, time source and
    declarations): the runtime's modules and a new declaration kind build on it; node code
    uses the methods here."""

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
        self._machine_clock = clock
        self._use_sim_time = config.use_sim_time
        self.kind = config.kind
        self.started_ns = time.time_ns() if started_ns is None else started_ns
        self._connect, self._domain, self._credentials = config.connect, config.domain, config.credentials
        self.params: P = params
        self.world: World = config.world
        self.limits: Limits = config.limits
        self.session = session
        self.log = logging.getLogger(config.name)
        self.core = NodeCore(
            config.name,
            session,
            self.log,
            clock,
            time.time_ns,
            namespace=self.namespace,
            remaps=config.remaps,
            interface=config.interface,
        )
        self._own = OwnServices(self)  # every node's: its parameters, what it is, its log level, its types
        if config.use_sim_time:
            follow_clock(self.core)

    @property
    def interface(self) -> Interface | None:
        """What the node may declare (runtime.interface; None: anything)."""
        return self.core.interface

    @property
    def connect(self) -> str:
        """The router's endpoint the node reached (``turtlectl.Client(node.connect, node.domain)``:
        a client of the node's own system)."""
        return self._connect

    @property
    def domain(self) -> str:
        """The node's domain ("" for none)."""
        return self._domain

    @property
    def remaps(self) -> dict[str, str]:
        """Key as written -> key used (its launch file's ``remap`` of the node)."""
        return self.core.remaps

    @property
    def clock(self) -> Callable[[], float]:
        """The node's clock: ``node.clock()`` is the time in s its timers run on (monotonic; the
        simulated time with ``use_sim_time``; a fake one under ``FakeNode``)."""
        return self.core.clock

    def now_ns(self) -> int:
        """The node's time in ns since the Unix epoch, what its messages are stamped with: the
        wall clock, or with ``use_sim_time`` the simulated one (0 before the simulator's first
        ``Clock``)."""
        return self.core.now_ns()

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
        sim = self.core.sim
        if sim is not None and sim.declared is not None:  # it makes the time: it does not follow it
            sim.declared.undeclare()
        self.core.set_time_source(self._machine_clock, now_ns)

    # -- declarations -------------------------------------------------------
    def resolve(self, key: str) -> str:
        """The key this node uses for ``key`` as written (messages.keys.resolve): as written
        outside a namespace; in ``turtle2``, ``turtle1/pose`` is ``turtle2/pose`` and
        ``robot/status`` is ``turtle2/robot/status``; ``/turtles`` is always ``turtles``; then
        the launch file's ``remap`` of the node (``remaps``)."""
        return self.core.resolve(key)

    def publisher(self, key: str, msg_type: type[M]) -> Publisher[M]:
        """A publisher of ``msg_type`` on ``key`` (``publish``; ``undeclare`` withdraws it)."""
        return declarations.publisher(self.core, key, msg_type)

    def subscribe(self, key: str, msg_type: type[M], callback: Callable[[M], None]) -> Declaration:
        """Call ``callback(msg)`` on the node thread for each valid ``msg_type`` on ``key``,
        until the returned declaration is undeclared."""
        return declarations.subscription(self.core, key, msg_type, callback)

    def latest(self, key: str, msg_type: type[M], keep: int = RING, follow: bool = False) -> Latest[M]:
        """Keep the newest ``msg_type`` on ``key`` for the node to read at its own pace
        (``.get()``; every one since the last read: ``.received()``, up to ``keep``), without
        waking the node for each message (see ``Latest``); ``follow``: it will also take every
        message at times (``.each(callback)``), ready from now on."""
        return declarations.latest(self.core, key, msg_type, keep, follow)

    def serve(
        self,
        key: str,
        request_type: type[M],
        response_type: type[Message],
        handler: Callable[[Request[M]], None],
    ) -> Declaration:
        """Serve a queryable; ``handler(request)`` runs on the node thread and responds when it
        likes, until the returned declaration is undeclared."""
        return declarations.service(self.core, key, request_type, response_type, handler)

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
        return declarations.json_answer(self.core, key, document)

    def watch_liveliness(self, key_expr: str, callback: Callable[[str, bool], None]) -> Declaration:
        """Call ``callback(key, alive)`` on the node thread when a matching token appears or
        vanishes, until the returned declaration is undeclared."""
        return declarations.liveliness_watch(self.core, key_expr, callback)

    def timer(self, period: float, callback: Callable[[], None]) -> Timer:
        """Call ``callback()`` every ``period`` s on an absolute schedule (until paused)."""
        return self.core.timer(period, callback)

    def on_params(self, callback: Callable[[P], None]) -> None:
        """Call ``callback(params)`` on the node thread after a parameter changed at run time
        (``self.params`` is already the new Struct): a node that keeps something made from a
        parameter (a timer's period, a table of beam angles) makes it again here.  A node that
        reads ``node.params`` where it uses them needs no hook."""
        self._own.on_params(callback)

    def on_shutdown(self, callback: Callable[[], None]) -> None:
        """Run ``callback()`` on the node thread when the node stops (e.g. to stop the turtle)."""
        self.core.on_shutdown(callback)

    # -- running ------------------------------------------------------------
    @property
    def stopping(self) -> bool:
        """Whether ``stop`` was asked for (a signal, the parent's death, the node itself)."""
        return self.core.stop_requested

    def stop(self, *_: Any) -> None:
        """Ask the node to stop (safe from signal handlers and other threads)."""
        self.core.stop()

    def spin(self) -> bool:
        """Run timers and queued callbacks on this thread until ``stop``, then the shutdown
        hooks.  Returns False if node code raised: the traceback is logged once and the
        node stops as if asked to (its hooks still run, so a navigator still stops the turtle)."""
        return self.core.run()

    def spin_once(self, timeout: float = 0.0) -> bool:
        """One turn of ``spin`` on the calling thread, for a script or test that drives the node
        itself (as rclpy's ``spin_once``): the timers due fire, then one queued callback runs,
        waited for at most ``timeout`` s.  True if a callback ran.  Node code that raises
        propagates."""
        return self.core.run_once(timeout)

    def spin_until(self, condition: Callable[[], object], timeout: float) -> bool:
        """``spin_once`` until ``condition()`` is true or ``timeout`` s (the machine's clock) have
        passed (as rclpy's ``spin_until_future_complete``: ``spin_until(future.done, 5.0)``).
        Whether ``condition()`` held."""
        deadline = time.monotonic() + timeout
        while not condition():
            left = deadline - time.monotonic()
            if left <= 0:
                return bool(condition())
            self.core.run_once(min(left, 0.1))
        return True

    def shutdown(self) -> None:
        """Run the shutdown hooks once, each even if an earlier one raised."""
        self.core.shutdown()
