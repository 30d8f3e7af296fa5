"""A goal service, as a ROS 2 action: ``Node.goal_server`` serves one, ``Node.goal_client``
calls one (``runtime.goal_client``).

The wire (docs/interfaces.md, "Goal services"), for a goal service on ``KEY`` with its goal,
feedback and result types:

* ``KEY`` is a queryable: a goal is a query carrying the goal; its replies are feedback
  (any number, while the goal runs) and then one result, the last reply.  A goal refused
  gets its result at once, as the only reply;
* ``KEY/cancel`` answers a ``Cancel`` (its ``reason``, default "canceled", is passed on)
  with an ``Ack`` (``ok`` false: no goal was running);
* ``KEY/feedback`` carries the same feedback for observers;
* the caller holds a liveliness token ``@turtlectl/client/<id>`` while it waits; when it
  vanishes the goal ends "caller gone".  ``<id>`` is the goal's own ``client`` field when
  its type has one and it is not empty (``NavigateToRequest.client``), else the query's
  attachment (UTF-8).

The server does, once for every user: refusal before anything else (a refused goal never
touches the running one, as rclpy's goal callback), one goal at a time with preemption by a
newer one, the cancel service, the caller going away, a deadline (``timeout``, changeable
while it runs), feedback at a rate, the node shutting down, and exactly one result per goal.
How a goal ended is told to the user's ``on_cancel(goal, reason)``, which gives the result.
Every callback runs on the node's thread.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Generic, TypeVar

from turtlectl.messages import Ack, Cancel, Message
from turtlectl.messages.keys import CLIENT_TOKEN_PREFIX
from turtlectl.runtime.goal_reasons import CALLER_GONE, CANCELED, PREEMPTED, SHUT_DOWN, TIMEOUT
from turtlectl.runtime.handles import Declaration

if TYPE_CHECKING:
    from turtlectl.runtime.entities import Request
    from turtlectl.runtime.node import Node

__all__ = [
    "CALLER_GONE",
    "GOAL_ROLES",
    "CANCELED",
    "PREEMPTED",
    "SHUT_DOWN",
    "TIMEOUT",
    "GoalHandle",
    "GoalServer",
    "caller_key",
]

G = TypeVar("G", bound=Message)
F = TypeVar("F", bound=Message)
R = TypeVar("R", bound=Message)


#: the graph's roles of a goal service's three types (liveliness tokens on KEY: ``turtlectl action list``)
GOAL_ROLES = ("goal", "goal_feedback", "goal_result")

_MIN_PERIOD = 1e-3  # s: a timer's shortest period (a deadline already past fires at the next turn)


def caller_key(goal: Message, attachment: bytes | None) -> str:
    """The liveliness key of a goal's caller: ``@turtlectl/client/<id>``, ``<id>`` from the
    goal's ``client`` field, else the query's attachment; "" when it names none."""
    client = getattr(goal, "client", "")
    if not (isinstance(client, str) and client):
        client = (attachment or b"").decode("utf-8", "replace")
    return f"{CLIENT_TOKEN_PREFIX}/{client}" if client and "/" not in client else ""


def summary(goal: Message) -> str:
    """A goal in a few words for the cancel's ``Ack``: its fields' values (``(8, 5, 90)``), the
    caller's ``client`` left out."""
    values = []
    for name in goal.__struct_fields__:
        if name in ("client", "stamp", "seq"):
            continue
        value = getattr(goal, name)
        values.append(f"{value:g}" if isinstance(value, float) else str(value))
    return f"({', '.join(values)})"


class GoalHandle(Generic[G, F, R]):
    """One goal a goal server accepted, handed to its ``execute``: ``request`` (the goal),
    ``started`` (s, the node's clock), ``caller`` (its caller's liveliness key, "" if none),
    ``summary`` (how the cancel's Ack names it; set it to your own words), ``end_detail`` (the
    ``detail`` of the ``Cancel`` that ended it: its canceller's words, "" if none).  ``feedback(msg)``
    sends progress, ``finish(result)`` ends it: both from any callback of the node."""

    def __init__(self, server: GoalServer[G, F, R], request: Request[G], started: float, caller: str):
        self.request: G = request.body
        self.id = next(_ids)
        self.started = started
        self.caller = caller
        self.summary = summary(request.body)
        self.end_detail = ""
        self._server = server
        self._call = request

    @property
    def active(self) -> bool:
        """Whether it runs (no result sent yet)."""
        return not self._call.done

    def feedback(self, feedback: F) -> F | None:
        """Send ``feedback`` to the caller (a reply) and to observers (``KEY/feedback``), stamped
        once for both; None (nothing sent) once the goal has ended."""
        if not self.active:
            return None
        stamped = self._server._feedback_pub.publish(feedback)
        self._call.respond(stamped, final=False)
        return stamped

    def finish(self, result: R) -> bool:
        """End the goal with ``result`` (success or not: the result type says); False if it
        had ended already (a goal has one result)."""
        if not self.active:
            return False
        if not isinstance(result, self._server.result_type):
            raise TypeError(f"a result of {self._server.key} is a {self._server.result_type.__name__}, not {result!r}")
        self._call.respond(result)
        self._server._ended(self)
        return True

    def __repr__(self) -> str:
        return f"<goal {self.id} {self.summary}{'' if self.active else ' (ended)'}>"


_ids = itertools.count(1)


class GoalServer(Generic[G, F, R]):
    """A goal service being served (``Node.goal_server`` makes it): ``goal`` is the running
    one's handle (None: idle); ``timeout`` and ``feedback_rate`` may change while it runs;
    ``cancel(reason)`` ends the running goal from the node's own code; ``undeclare()`` ends
    it ("shut down") and withdraws the service."""

    def __init__(
        self,
        node: Node[Any],
        declared: Declaration,
        key: str,
        types: tuple[type[G], type[F], type[R]],
        execute: Callable[[GoalHandle[G, F, R]], None],
        refuse: Callable[[G], R | None] | None,
        on_cancel: Callable[[GoalHandle[G, F, R], str], R | None] | None,
        feedback: Callable[[GoalHandle[G, F, R]], F | None] | None,
        feedback_rate: float,
        timeout: float | None,
    ):
        self.goal_type, self.feedback_type, self.result_type = types
        self._node = node
        self._execute, self._refuse, self._feedback = execute, refuse, feedback
        self._on_cancel = on_cancel or _default_result(self.result_type)
        self.goal: GoalHandle[G, F, R] | None = None
        self._timeout = timeout
        self._rate = feedback_rate
        if feedback_rate <= 0:
            raise ValueError(f"feedback_rate must be above 0 Hz (got {feedback_rate:g})")
        self.declared = declared  # what it is made of: its services, its feedback topic, its timers, its tokens
        self.key = declared.key
        parts = [
            node.serve(key, self.goal_type, self.result_type, self._on_goal),
            node.serve(f"{key}/cancel", Cancel, Ack, self._on_cancel_request),
            node.watch_liveliness(f"{CLIENT_TOKEN_PREFIX}/**", self._on_token),
        ]
        self._feedback_pub = node.publisher(f"{key}/feedback", self.feedback_type)
        self._deadline = node.timer(1.0, self._on_deadline)
        self._ticker = node.timer(1.0 / feedback_rate, self._on_tick)
        for part in (*parts, self._feedback_pub, self._deadline, self._ticker):
            self.declared.add(part)
        self._deadline.pause()
        self._ticker.pause()
        node.on_shutdown(lambda: self._end(SHUT_DOWN))

    # -- settings ----------------------------------------------------------------
    @property
    def timeout(self) -> float | None:
        """s a goal may run before it ends "timeout" (None: no limit)."""
        return self._timeout

    @timeout.setter
    def timeout(self, seconds: float | None) -> None:
        self._timeout = seconds
        self._arm()

    @property
    def feedback_rate(self) -> float:
        """Hz at which ``feedback(goal)`` is asked for while a goal runs."""
        return self._rate

    @feedback_rate.setter
    def feedback_rate(self, hz: float) -> None:
        if hz <= 0:
            raise ValueError(f"feedback_rate must be above 0 Hz (got {hz:g})")
        self._rate = hz
        self._ticker.retime(1.0 / hz)
        if self.goal is None:
            self._ticker.pause()

    # -- the node's own code ---------------------------------------------------------
    def cancel(self, reason: str = CANCELED) -> bool:
        """End the running goal with ``reason`` (``on_cancel`` gives its result); False: none ran."""
        return self._end(reason or CANCELED)

    def undeclare(self) -> None:
        """End the running goal ("shut down") and withdraw the service.  Idempotent."""
        if self.declared.active:
            self._end(SHUT_DOWN)
            self.declared.undeclare()

    # -- what comes in -----------------------------------------------------------------
    def _on_goal(self, request: Request[G]) -> None:
        if self._refuse is not None:
            refusal = self._refuse(request.body)
            if refusal is not None:  # the running goal is untouched
                request.respond(refusal)
                return
        self._end(PREEMPTED)
        now = self._node.clock()
        goal = self.goal = GoalHandle(self, request, now, caller_key(request.body, request.attachment))
        self._ticker.retime(1.0 / self._rate, now)
        self._ticker.resume(now)
        self._arm()
        self._execute(goal)
        if self.goal is goal:  # feedback at once: the caller knows its goal runs, then every period
            self._on_tick()

    def _on_cancel_request(self, request: Request[Cancel]) -> None:
        goal = self.goal
        if goal is None:
            request.respond(Ack(ok=False, detail="no goal is running"))
            return
        goal.end_detail = request.body.detail
        self._end(request.body.reason or CANCELED)
        request.respond(Ack(detail=f"canceled the goal {goal.summary}"))

    def _on_token(self, key: str, alive: bool) -> None:
        if not alive and self.goal is not None and self.goal.caller and key == self.goal.caller:
            self._end(CALLER_GONE)

    def _on_deadline(self) -> None:
        goal, timeout = self.goal, self._timeout
        if goal is None or timeout is None:
            return
        left = goal.started + timeout - self._node.clock()
        if left > 1e-9:  # the timeout grew meanwhile
            self._arm()
        else:
            self._end(TIMEOUT)

    def _on_tick(self) -> None:
        goal = self.goal
        if goal is not None and self._feedback is not None:
            feedback = self._feedback(goal)
            if feedback is not None:
                goal.feedback(feedback)

    # -- inside ------------------------------------------------------------------------
    def _arm(self) -> None:
        """The deadline timer due when the running goal's time is up (paused: none, or no limit)."""
        goal, timeout = self.goal, self._timeout
        if goal is None or timeout is None:
            self._deadline.pause()
            return
        now = self._node.clock()
        self._deadline.retime(max(_MIN_PERIOD, goal.started + timeout - now), now)
        self._deadline.resume(now)

    def _end(self, reason: str) -> bool:
        """End the running goal: ``on_cancel`` says its result (or finishes it itself)."""
        goal = self.goal
        if goal is None:
            return False
        result = self._on_cancel(goal, reason)
        if goal.active:
            goal.finish(result if result is not None else _default_result(self.result_type)(goal, reason))
        return True

    def _ended(self, goal: GoalHandle[G, F, R]) -> None:
        if self.goal is goal:
            self.goal = None
            self._ticker.pause()
            self._deadline.pause()

    def __repr__(self) -> str:
        return f"<goal service on {self.key}{'' if self.declared.active else ' (undeclared)'}>"


def _default_result(result_type: type[R]) -> Callable[[GoalHandle[Any, Any, R], str], R]:
    """The result of a goal ended by the server when no ``on_cancel`` is given: the result
    type's ``success=False`` and ``reason``, those of its fields it has.  TypeError (when the
    goal server is declared) if it cannot be made so."""
    fields = result_type.__struct_fields__

    def make(goal: GoalHandle[Any, Any, R], reason: str) -> R:
        given = {"success": False, "reason": reason}
        return result_type(**{k: v for k, v in given.items() if k in fields})

    try:
        make(None, "")  # type: ignore[arg-type]
    except TypeError as exc:
        raise TypeError(
            f"give the goal server an on_cancel(goal, reason) that returns a {result_type.__name__}: "
            f"one cannot be made from success and reason alone ({exc})"
        ) from None
    return make
