"""A node's client of a goal service (``Node.goal_client``), as rclpy's ``ActionClient``: send a
goal, receive its feedback, cancel it, get its result as a ``Future`` (runtime.futures).  The
wire is runtime.goals'.  Every callback runs on the node's thread.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Generic, TypeVar

import msgspec

from turtlectl.messages import Ack, Cancel, ErrorReply, Message
from turtlectl.runtime.client.errors import Failed
from turtlectl.runtime.futures import Future
from turtlectl.runtime.handles import Declaration

if TYPE_CHECKING:
    from turtlectl.runtime.node import Node

__all__ = ["GoalClient", "GoalFailed", "GoalFuture"]

G = TypeVar("G", bound=Message)
F = TypeVar("F", bound=Message)
R = TypeVar("R", bound=Message)

NO_LIMIT = 24 * 3600.0  # s: a goal's query stays open until its result (the server's own timeout decides)


class GoalFailed(Failed):
    """A goal that got no result (exit code 1): ``why`` says which way, for the goal service
    ``key``: ``unserved`` (nothing serves it), ``refused`` (the server refused the request as
    unreadable: its ErrorReply's ``error``), ``gone`` (its server ``node``, pid ``pid``, went
    away before answering), ``no_result`` (its replies ended without one), ``unconfirmed``
    (nobody confirmed a cancel)."""

    def __init__(self, key: str, why: str, *, node: str = "", pid: int = 0, error: str = ""):
        texts = {
            "unserved": f"nothing serves {key} (is its node running?)",
            "refused": f"{key} refused the goal: {error}",
            "gone": f"{key}'s server {node} (pid {pid}) went away before the goal ended",
            "no_result": f"{key} ended without a result (its server stopped answering: did it exit?)",
            "unconfirmed": f"nobody confirmed the cancel on {key}/cancel",
        }
        super().__init__(texts[why])
        self.key, self.why, self.node, self.pid, self.error = key, why, node, pid, error


class GoalFuture(Future[R]):
    """The result of one goal sent: a ``Future`` (``then``, ``add_done_callback``, ``result``
    once done), and ``cancel_goal(reason)`` to ask the server to end it."""

    def __init__(self, client: GoalClient[Any, Any, R]) -> None:
        super().__init__(threading.get_ident())  # resolved on the node's thread, which sends it
        self._client = client

    def cancel_goal(self, reason: str = "") -> Future[Ack]:
        """Ask the server to end this goal (if it still runs): a future of its Ack."""
        if self.done():
            done: Future[Ack] = Future()
            done.set_result(Ack(ok=False, detail="the goal had ended"))
            return done
        return self._client.cancel(reason)


class GoalClient(Generic[G, F, R]):
    """A client of the goal service ``key`` (``Node.goal_client`` makes it).  While declared it
    holds the caller token its goals name: they end ("caller gone") if the node goes away.
    ``server_seen`` is told each server's token as it comes and goes (on the node's thread):
    the last one gone is logged once (WARNING) and ends the running goals with GoalFailed
    naming it; one back is logged once (INFO)."""

    def __init__(
        self,
        node: Node[Any],
        declared: Declaration,
        key: str,
        types: tuple[type[G], type[F], type[R]],
        client_id: str,
    ):
        self.key = key  # as written: the node's calls resolve it
        self.goal_type, self.feedback_type, self.result_type = types
        self.client_id = client_id
        self.declared = declared
        self._node = node
        self.servers: set[tuple[str, int]] = set()  # (node, pid) of each live server of ``key``
        self._gone: tuple[str, int] | None = None  # the last server to leave, while none is back
        self._running: set[GoalFuture[R]] = set()  # goals sent, not ended

    def server_seen(self, alive: bool, node: str, pid: int) -> None:
        """A server of ``key`` (``node``, process ``pid``) appeared (``alive``) or went away."""
        if alive:
            self.servers.add((node, pid))
            if self._gone is not None:
                self._gone = None
                self._node.log.info("%s is served again: %s (pid %d) is back", self.key, node, pid)
            return
        if (node, pid) not in self.servers:
            return
        self.servers.discard((node, pid))
        if self.servers:
            return  # another still serves it
        self._gone = (node, pid)
        self._node.log.warning(
            "%s's server %s (pid %d) went away (it exited, or its host is cut off): goals to it fail until it is back",
            self.key,
            node,
            pid,
        )
        for future in list(self._running):
            future.set_exception(GoalFailed(self.key, "gone", node=node, pid=pid))
        self._running.clear()

    def send(
        self,
        goal: G,
        on_feedback: Callable[[F], None] | None = None,
        timeout: float | None = None,
    ) -> GoalFuture[R]:
        """Send ``goal``: a future of its result (a refused goal's too: the result type says).
        ``on_feedback(feedback)`` runs on the node thread for each feedback as it comes.
        ``timeout``: s to wait for the result (None: as long as the server lets the goal run);
        the future then ends with ``GoalFailed``.  A goal type with a ``client`` field names
        this client's token in it; any other carries it as the query's attachment."""
        if not isinstance(goal, self.goal_type):
            raise TypeError(f"a goal of {self.key} is a {self.goal_type.__name__}, not {goal!r}")
        if "client" in self.goal_type.__struct_fields__ and not getattr(goal, "client", ""):
            goal = msgspec.structs.replace(goal, client=self.client_id)  # type: ignore[call-arg]
        future: GoalFuture[R] = GoalFuture(self)
        self._running.add(future)
        future.add_done_callback(self._running.discard)
        result_type, feedback_type = self.result_type, self.feedback_type

        def on_reply(message: Message) -> None:
            if future.done():
                return  # ended here already (its server went away)
            if isinstance(message, result_type):
                future.set_result(message)
            elif isinstance(message, feedback_type) and on_feedback is not None and not future.done():
                on_feedback(message)
            elif isinstance(message, ErrorReply):
                future.set_exception(GoalFailed(self.key, "refused", error=message.error))

        def on_done(replies: list[Message]) -> None:
            if future.done():
                return
            if not replies:
                future.set_exception(GoalFailed(self.key, "unserved"))
            elif self._gone is not None:
                node, pid = self._gone
                future.set_exception(GoalFailed(self.key, "gone", node=node, pid=pid))
            else:
                future.set_exception(GoalFailed(self.key, "no_result"))

        self._node.call(
            self.key,
            goal,
            on_done,
            NO_LIMIT if timeout is None else timeout,
            on_reply=on_reply,
            attachment=self.client_id.encode(),
        )
        return future

    def cancel(self, reason: str = "") -> Future[Ack]:
        """Ask ``KEY/cancel`` to end the running goal (``reason``: what its caller is told):
        a future of the server's Ack (``ok`` false: no goal was running); ``GoalFailed`` if
        nobody answers."""

        def ack(replies: list[Message]) -> Ack:
            for reply in replies:
                if isinstance(reply, Ack):
                    return reply
            raise GoalFailed(self.key, "unconfirmed")

        return self._node.call(f"{self.key}/cancel", Cancel(reason=reason)).then(ack)

    def undeclare(self) -> None:
        """Give up the caller token (a goal still running ends "caller gone").  Idempotent."""
        self.declared.undeclare()
