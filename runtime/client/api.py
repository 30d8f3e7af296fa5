"""``turtlectl.Client``: a running system from a Python script, as the command line sees it.

One client session to the router, opened by the constructor and closed (bounded) by
``close`` or the ``with`` block.  Each method does what its command does, through the same
functions (``goto`` is ``turtlectl goto``: a client token, feedback, a timeout or Ctrl-C
cancels the goal and checks the cancel), and raises what the command would exit with:
``turtlectl.Error`` subclasses whose ``exit_code`` is the command's (docs/reference/exit-codes.md).
"""

from __future__ import annotations

import atexit
import contextlib
import os
import threading
import time
from collections.abc import Callable
from types import TracebackType
from typing import Any

import zenoh

from turtlectl.messages import (
    Ack,
    Cancel,
    Message,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    encode,
    encoding_for,
)
from turtlectl.messages.codec import type_name
from turtlectl.messages.keys import (
    FIRST_TURTLE,
    NAVIGATE_TO,
    NodeDetails,
    node_key,
    param_set_key,
    params_key,
    resolve,
    service_types,
)
from turtlectl.messages.stamps import with_stamp
from turtlectl.messages.world import World
from turtlectl.runtime.client import answers, goals, presence
from turtlectl.runtime.client.checks import endpoint, turtle_name
from turtlectl.runtime.client.errors import BadInput, Failed, Unreachable
from turtlectl.runtime.client.graph import GoalRow, Graph, NodeRow, ServiceRow, TopicRow
from turtlectl.runtime.client.services import CALL_TIMEOUT, NoAnswer, NobodyServes, Raw, Rejected, hinted, replies
from turtlectl.runtime.client.session import check_key, client_session, live_graph, live_turtle_namespace, require
from turtlectl.runtime.client.subscription import Subscription
from turtlectl.runtime.client.typebook import TypeBook
from turtlectl.runtime.endpoint import CONNECT_ENV, DEFAULT_ENDPOINT, default_domain
from turtlectl.runtime.futures import Future
from turtlectl.runtime.goal_reasons import CANCELED
from turtlectl.runtime.handles import Declaration


class Client:
    """A client of a running system: ``with Client() as client: client.goto(8, 5, 90)``.

    ``connect``: the router's endpoint (default: ``TURTLECTL_CONNECT``, else
    ``tcp/127.0.0.1:7447``); ``domain``: the system's domain (default: ``TURTLECTL_DOMAIN``);
    ``turtle``: the turtle whose nodes it talks to: with ``turtle="turtle2"``, ``goto`` calls
    ``turtle2/navigate_to``, every key it is given is read as a node of namespace turtle2 writes
    it (``robot/status`` is ``turtle2/robot/status``, ``turtle1/pose`` is ``turtle2/pose``,
    ``/turtles`` is ``turtles``) and every node name the same way (``navigator`` is
    ``turtle2/navigator``, ``/sim`` is ``sim``): one rule, messages.keys.resolve.  turtle1's
    nodes run in the namespace the running system gives them (outside any in the default launch
    file, ``turtle1`` when a launch file puts them there), as any turtle's.  Without ``turtle``,
    keys and node names are taken as written, and ``goto`` and ``cancel`` drive turtle1.
    ``role``: the login it uses on a ``launch --secure`` system (default: ``TURTLECTL_ROLE``,
    else operator); ``timeout_named``: how its errors name a goal's timeout (``timeout={:g} s``;
    the command line's, ``--timeout {:g} s``).
    Raises ``turtlectl.Error`` (``Unreachable``, exit code 3) if no router answers."""

    def __init__(
        self,
        connect: str | None = None,
        domain: str | None = None,
        turtle: str = "",
        *,
        role: str | None = None,
        timeout_named: str = goals.API_LIMIT,
    ) -> None:
        self.connect = endpoint(connect or os.environ.get(CONNECT_ENV, DEFAULT_ENDPOINT))
        self.domain = default_domain() if domain is None else domain
        self.turtle = turtle_name(turtle)  # BadInput for a name that is none
        self._timeout_named = timeout_named
        self._stack = contextlib.ExitStack()
        self._session: zenoh.Session = self._stack.enter_context(client_session(self.connect, self.domain, role))
        #: the namespace its keys and node names are resolved in (the turtle's nodes'; "" without a turtle)
        self.namespace = live_turtle_namespace(self._session, self.turtle)
        self._driven: str | None = None if not self.turtle else self.namespace  # goto's and cancel's
        self._publishers: dict[str, presence.Announced] = {}
        self._sent: dict[str, int] = {}  # each topic's count of messages published (their seq)
        self._declared: list[Declaration] = []  # its subscriptions, undeclared by close
        self._book = TypeBook(self._session)  # the message types it has learnt from the nodes
        self._lock = threading.Lock()
        # a script that ends without close(): closed while the interpreter can still run Zenoh's
        # callbacks (after, a subscription's callback waited for Python forever and the script hung)
        atexit.register(self.close)

    def close(self) -> None:
        """Undeclare what this client declared and close its session (bounded); idempotent.
        A client left open is closed when the script ends."""
        atexit.unregister(self.close)
        with self._lock:
            for pub in self._publishers.values():
                pub.undeclare()
            self._publishers.clear()
        for declared in list(self._declared):
            declared.undeclare()
        self._stack.close()

    def __enter__(self) -> Client:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None, tb: TracebackType | None) -> None:
        self.close()

    # goals -------------------------------------------------------------------------------------

    def goto(
        self,
        x: float,
        y: float,
        theta: float,
        *,
        timeout: float | None = None,
        on_feedback: Callable[[NavigateToFeedback], None] | None = None,
    ) -> NavigateToResponse:
        """Drive to (``x``, ``y``) m facing ``theta`` degrees and wait for the outcome: the
        navigator's ``NavigateToResponse`` when it ends the goal (``success`` says whether it
        was reached; ``reason`` why not: refused, blocked, its own goal_timeout, preempted, ...).
        ``on_feedback`` gets each feedback as it arrives.  A goal canceled raises
        ``GoalCanceled`` (exit 1), whoever canceled it: this call's ``timeout`` (s; default:
        none but the navigator's goal_timeout) or a cancel (``cancel()``, ``turtlectl
        cancel``); it carries the navigator's ``response`` (the final pose) and the last
        ``feedback``.  A KeyboardInterrupt cancels the goal too: ``Interrupted`` (130).  A cancel
        nobody confirmed: ``CancelUnconfirmed`` (5: the turtle may still drive)."""
        request = NavigateToRequest(x=float(x), y=float(y), theta=float(theta))
        return self._run_goal(goals.navigate_to(self._goal_key(NAVIGATE_TO)), request, timeout, on_feedback)  # type: ignore[no-any-return]

    def cancel(self, service: str = NAVIGATE_TO, reason: str = "", detail: str = "") -> Ack:
        """Cancel the running goal of the goal service ``service`` (default ``navigate_to``);
        the server's Ack (``ok`` false: no goal was running).  ``reason`` and ``detail``: what the
        goal's caller is told (``Cancel``'s; default: the server's own words for a cancel)."""
        cancel_key = f"{check_key(self._goal_key(service))}/cancel"
        request = Cancel(reason=reason, detail=detail)
        with self._hinted():
            answers = list(replies(self._session, cancel_key, request, CALL_TIMEOUT, goal=True))
        answer = answers[-1] if answers else None
        if not isinstance(answer, Ack):
            raise Failed(f"{cancel_key} answered {type_name(type(answer))}, not {type_name(Ack)}")
        return answer

    def send_goal(
        self,
        service: str,
        goal: Message,
        on_feedback: Callable[[Message], None] | None = None,
        *,
        timeout: float | None = None,
    ) -> Future[Message]:
        """Send ``goal`` to the goal service ``service`` (any node's ``Node.goal_server``:
        ``turtlectl action list``) without waiting: a ``Future`` of its result (``result(timeout)``
        waits; a refused goal's result too).  ``on_feedback`` gets each feedback on the goal's
        own thread.  While it waits the client holds a caller token (the goal ends if the
        script goes away).  As with ``goto``, a goal canceled ends the future with
        ``GoalCanceled`` (carrying the server's result and the last feedback), whoever canceled
        it: ``timeout`` s (default: the server's own), or ``cancel(service)`` meanwhile; a
        cancel nobody confirmed, with ``CancelUnconfirmed``."""
        goal_service = self._goal_service(service)
        future: Future[Message] = Future()

        def run() -> None:
            try:
                future.set_result(self._run_goal(goal_service, goal, timeout, on_feedback))
            except BaseException as exc:  # the script's to see, through the future
                future.set_exception(exc)

        threading.Thread(target=run, name=f"goal {goal_service.key}", daemon=True).start()
        return future

    def run_goal(
        self,
        service: str,
        goal: Message,
        on_feedback: Callable[[Message], None] | None = None,
        *,
        timeout: float | None = None,
    ) -> Message:
        """``send_goal`` on this thread: wait for the result of ``goal`` and return it (the same
        errors, raised here).  A KeyboardInterrupt cancels the goal: ``Interrupted`` (130)."""
        return self._run_goal(self._goal_service(service), goal, timeout, on_feedback)  # type: ignore[no-any-return]

    def goal_service(self, service: str) -> GoalRow:
        """The goal service ``service`` as the graph lists it (its types, its servers), its
        types learnt from the nodes; ``Unreachable`` if none runs."""
        key = check_key(self._key(service))
        row = next((row for row in self.goals() if row.key == key), None)
        if row is None:
            raise Unreachable(f"no goal service {key} is running (`turtlectl action list` lists them)")
        self._book.learn_all()  # its feedback and result types, as the nodes describe them
        return row

    def _goal_service(self, service: str) -> goals.GoalService:
        row = self.goal_service(service)
        return goals.GoalService(row.key, row.result, tuple(row.servers))

    def _run_goal(
        self,
        service: goals.GoalService,
        goal: Message,
        timeout: float | None,
        on_feedback: Callable[[Any], None] | None,
    ) -> Any:
        """The one way every goal of this client runs (``goto``, ``send_goal``, ``run_goal``):
        the result of ``goal`` (goals.run_goal), or GoalCanceled for one canceled by anyone, as
        for one its own ``timeout`` canceled: one rule for both."""
        last: list[Any] = [None]  # the goal's last feedback, for the error

        def feedback(message: Any) -> None:
            last[0] = message
            if on_feedback is not None:
                on_feedback(message)

        limit = goals.NO_LIMIT if timeout is None else timeout
        with self._hinted():
            result = goals.run_goal(self._session, service, goal, limit, feedback, self._timeout_named)
        if getattr(result, "reason", "") == CANCELED and getattr(result, "success", False) is False:
            raise goals.canceled(service, result, last[0])
        return result

    @property
    def session(self) -> zenoh.Session:
        """Its Zenoh session (in its domain, with its login), for a tool built on this client
        (``turtlectl teleop``); closed by ``close``."""
        return self._session

    @property
    def driven(self) -> str:
        """The namespace of the turtle ``goto`` and ``cancel`` drive: this client's turtle's,
        turtle1's without one (asked of the running system once)."""
        if self._driven is None:
            self._driven = live_turtle_namespace(self._session, FIRST_TURTLE)
        return self._driven

    def _key(self, key: str) -> str:
        """``key`` as a node of this client's turtle writes it (messages.keys.resolve); a node's
        name the same way (``navigator`` in turtle2 is ``turtle2/navigator``)."""
        return resolve(key, self.namespace)

    def _goal_key(self, key: str) -> str:
        """``key`` of the turtle ``goto`` and ``cancel`` drive: this client's, or turtle1 without one."""
        return resolve(key, self.driven)

    # topics ------------------------------------------------------------------------------------

    def publish(self, topic: str, message: Message) -> None:
        """Publish ``message`` on ``topic``, stamped as a node's publisher stamps it (messages.stamps:
        ``stamp`` now, ``seq`` its count on ``topic``); its publisher is kept until ``close``."""
        key = check_key(self._key(topic), publish=True)
        require(self._session, "publish", key)
        with self._lock:
            pub = self._publishers.get(key)
            if pub is None:
                pub = presence.publisher(self._session, key, type_name(type(message)), encoding_for(type(message)))
                self._publishers[key] = pub
            seq = self._sent[key] = self._sent.get(key, -1) + 1
        pub.put(encode(with_stamp(message, time.time_ns, seq)))

    def subscribe(self, topic: str, callback: Callable[[Message], None] | None = None) -> Subscription:
        """Messages on ``topic`` (a key expression: ``robot/status``, ``turtle1/*``), decoded."""
        key = check_key(self._key(topic))
        require(self._session, "subscribe", key)
        if callback is not None:  # a callback runs on Zenoh's thread, which must not ask: learn the topic's types now
            for row in self.topics():
                if zenoh.KeyExpr(row.key).intersects(zenoh.KeyExpr(key)):
                    self._book.resolve(row.type)
        return Subscription(self._declared, self._session, key, callback, self._book)

    def latest(self, topic: str, timeout: float = 5.0) -> Message:
        """The next message on ``topic``; ``Failed`` (exit 1) if none comes within ``timeout`` s."""
        sub = self.subscribe(topic)
        try:
            return sub.next(timeout)
        except Failed:
            raise Failed(f"no message on {self._key(topic)} within {timeout:g} s") from None
        finally:
            sub.undeclare()

    # services ----------------------------------------------------------------------------------

    def call(self, service: str, request: Message, timeout: float = CALL_TIMEOUT) -> Message:
        """Call ``service`` and return its last reply (a goal service's response, after its
        feedback).  ``Unreachable`` if nothing serves it; ``BadInput`` if it refuses the request."""
        key = check_key(self._key(service))
        if not service_types(key):  # a service of the user's: its answer's type from the nodes' descriptions
            self._book.learn_all()
        with self._hinted():
            answers = list(replies(self._session, key, request, timeout))
        last = answers[-1] if answers else None
        if not isinstance(last, Message):
            raise Failed(f"{key} answered with something that is not a message")
        return last

    def call_all(
        self, service: str, request: Message, *, everyone: bool = False, timeout: float = CALL_TIMEOUT
    ) -> list[Message]:
        """Every reply of ``service`` to ``request`` (the messages among them), as they came;
        with ``everyone``, from every node that serves it (``reset``: the simulator's and each
        status monitor's).  ``Unreachable`` if nothing serves it."""
        key = check_key(self._key(service))
        with self._hinted():
            return [m for m in replies(self._session, key, request, timeout, everyone) if isinstance(m, Message)]

    # parameters --------------------------------------------------------------------------------

    def params(self, node: str) -> dict[str, Any]:
        """The parameters ``node`` runs with, by name (tables as dicts); ``node`` is resolved in
        this client's turtle's namespace, as keys are (``navigator`` in turtle2: ``turtle2/navigator``)."""
        node = self._key(node)
        got = self._asked(node, params_key(node), "with its parameters")
        if not got or not isinstance(got[-1], Raw):
            raise Failed(f"{node} sent no parameters")
        return answers.parse_params(node, got[-1].payload)

    def param(self, node: str, name: str) -> Any:
        """``node``'s parameter ``name`` (dotted into a table: ``gains.lookahead``)."""
        return answers.value(self.params(node), self._key(node), name)

    def node_info(self, node: str) -> NodeDetails:
        """What ``node`` says about itself: kind, pid, host, start time, log level, and how
        many records at ERROR or worse it has logged (``errors``, ``last_error``)."""
        node = self._key(node)
        return answers.parse_details(node, self._asked(node, node_key(node), "with what it is"))

    def _asked(self, node: str, key: str, what: str) -> list[Any]:
        """Every reply of ``node`` on ``key``; if it gives none, the command line's error: no node
        of that name runs (the live ones named), or it runs and did not answer (its pid)."""
        try:
            with self._hinted():
                return list(replies(self._session, key, b"", CALL_TIMEOUT))
        except (NobodyServes, NoAnswer) as exc:
            if isinstance(exc, NoAnswer) and exc.answered:
                raise
            waited = exc.timeout if isinstance(exc, NoAnswer) else None
            raise answers.unanswered(node, self.graph(), self.domain, what, waited) from None

    def set_param(self, node: str, name: str, value: Any) -> str:
        """Set ``node``'s parameter ``name`` to ``value`` while it runs; the node's answer.
        ``BadInput`` (exit 2) with the node's reason if it refuses (type, range, fixed)."""
        from turtlectl.messages import SetParameter

        node = self._key(node)
        try:
            with self._hinted():
                answer = self.call(param_set_key(node), SetParameter(name=name, value=value))
        except Rejected as exc:
            raise BadInput(exc.reason) from None
        if not isinstance(answer, Ack):
            raise Failed(f"{node} did not confirm the change")
        if not answer.ok:
            raise BadInput(answer.detail)
        return answer.detail

    # the world ---------------------------------------------------------------------------------

    def world(self) -> World:
        """The world the simulator declares: its size and obstacles (m); the default world
        when no simulator answers."""
        from turtlectl.runtime.client.services import world

        with self._hinted():
            return world(self._session)

    # the live graph ----------------------------------------------------------------------------

    def graph(self) -> Graph:
        """Nodes, clients, topics and services alive now (from liveliness, never cached); this
        client itself is not among the clients, nor its publishers and subscribers."""
        return live_graph(self._session, self.domain)

    def nodes(self) -> list[NodeRow]:
        """The nodes alive now: name, pid, host, uptime."""
        return self.graph().nodes

    def clients(self) -> list[NodeRow]:
        """The other clients with a session open (tools, scripts): name, tool, pid, host, uptime."""
        return self.graph().clients

    def topics(self) -> list[TopicRow]:
        """The topics in use now: key, type, publishers, subscribers."""
        return self.graph().topics

    def services(self) -> list[ServiceRow]:
        """The services served now: key, request type, servers."""
        return self.graph().services

    def goals(self) -> list[GoalRow]:
        """The goal services served now: key, goal, feedback and result types, servers."""
        return self.graph().goals

    def _hinted(self) -> contextlib.AbstractContextManager[None]:
        return hinted(self.connect, self.domain)


__all__ = ["Client"]
