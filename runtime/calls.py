"""What a node asks of others: queries (``Node.call``, a ``Future`` of the replies) and goal
services, as ROS 2 actions (``Node.goal_server`` serves one, ``Node.goal_client`` sends goals
to one).  ``NodeCalls`` is a base of ``runtime.node.Node``; it reaches the node only through its
core (runtime.core.NodeCore: ``declare``, ``enqueue``) and its public declarations (``serve``,
``publisher``, ...).
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Callable
from typing import TypeVar

import zenoh

from turtlectl.messages import Message, decode_any, encode
from turtlectl.messages.keys import ENTITY_TOKEN_PREFIX, client_token, parse_entity_token
from turtlectl.runtime.core import Kind, NodeCore
from turtlectl.runtime.entities import sample_encoding
from turtlectl.runtime.futures import Future
from turtlectl.runtime.goal_client import GoalClient
from turtlectl.runtime.goals import GOAL_ROLES, GoalHandle, GoalServer
from turtlectl.runtime.handles import Declaration
from turtlectl.runtime.interface import check

G = TypeVar("G", bound=Message)
F = TypeVar("F", bound=Message)
R = TypeVar("R", bound=Message)
_client_ids = itertools.count(1)


#: a goal service: its three graph tokens (``turtlectl action list``); the services and
#: publisher it is made of are checked against the interface as they are declared
GOAL_SERVICE = Kind("goal service", None, GOAL_ROLES)
#: a goal client: it calls the service's keys (its caller token is not an entity's)
GOAL_CLIENT = Kind("goal client", "call")


class NodeCalls:
    """``call``, ``goal_server`` and ``goal_client`` of a ``Node``, built on its ``core``
    (runtime.core.NodeCore) and its public declarations (``serve``, ``publisher``, ...)."""

    core: NodeCore

    # -- the API -------------------------------------------------------------------------------
    def call(
        self,
        key: str,
        request: Message,
        on_done: Callable[[list[Message]], None] | None = None,
        timeout: float = 1.0,
        *,
        on_reply: Callable[[Message], None] | None = None,
        attachment: bytes | None = None,
    ) -> Future[list[Message]]:
        """Query ``key`` with ``request`` without waiting: a ``Future`` of the replies that
        decoded (an error reply as ``ErrorReply``), done on the node thread once every server
        has answered (at once when nobody serves ``key``), bounded by ``timeout`` s.  Chain it
        (``then``, ``add_done_callback``: on the node thread), or give ``on_done(replies)``.
        ``on_reply(message)`` runs on the node thread for each reply as it comes (a goal's
        feedback); ``attachment``: bytes the query carries beside the request."""
        core = self.core
        key = core.resolve(key)
        check(core.name, core.interface, "call", key)
        core.uses(type(request))
        replies: list[Message] = []
        future: Future[list[Message]] = Future.of_node()
        if on_done is not None:
            future.add_done_callback(lambda done: on_done(done.result()))

        def on_zenoh_reply(reply: zenoh.Reply) -> None:  # Zenoh thread: decode and collect only
            sample = reply.ok if reply.ok is not None else reply.err
            try:
                message = decode_any(sample.payload.to_bytes())
            except (ValueError, AttributeError):
                return
            if on_reply is not None:
                core.enqueue(on_reply, message)
            replies.append(message)

        core.session.get(
            key,
            zenoh.handlers.Callback(on_zenoh_reply, lambda: core.enqueue(future.set_result, replies)),
            payload=encode(request),
            encoding=sample_encoding(type(request)),
            target=zenoh.QueryTarget.ALL,
            consolidation=zenoh.ConsolidationMode.NONE,
            timeout=timeout,
            attachment=attachment,
        )
        return future

    def goal_server(
        self,
        key: str,
        goal_type: type[G],
        feedback_type: type[F],
        result_type: type[R],
        *,
        execute: Callable[[GoalHandle[G, F, R]], None],
        refuse: Callable[[G], R | None] | None = None,
        on_cancel: Callable[[GoalHandle[G, F, R], str], R | None] | None = None,
        feedback: Callable[[GoalHandle[G, F, R]], F | None] | None = None,
        feedback_rate: float = 10.0,
        timeout: float | None = None,
    ) -> GoalServer[G, F, R]:
        """Serve goals on ``key``, as a ROS 2 action server (runtime.goals: the wire, and what the
        server does for you).  ``refuse(goal)``: a result refuses the goal (its only reply; the
        running goal is untouched), None accepts it.  ``execute(handle)``: an accepted goal
        starts (a newer one first ends the running goal, "preempted"); drive it from any
        callback, then ``handle.finish(result)``.  ``on_cancel(handle, reason)``: the server
        ends the goal (reason "preempted", "canceled" or a ``Cancel``'s own, "caller gone",
        "timeout", "shut down"): return its result (default: the result type's
        ``success=False``, ``reason``).  ``feedback(handle)``: the progress to send,
        ``feedback_rate`` Hz while a goal runs (None: nothing this time).  ``timeout``: s a goal
        may run (None: no limit; ``server.timeout`` changes it while running)."""
        types = (goal_type, feedback_type, result_type)
        return self.core.declare(
            GOAL_SERVICE,
            key,
            types,
            lambda d: GoalServer(self, d, key, types, execute, refuse, on_cancel, feedback, feedback_rate, timeout),
        )

    def goal_client(
        self, key: str, goal_type: type[G], feedback_type: type[F], result_type: type[R]
    ) -> GoalClient[G, F, R]:
        """A client of the goal service ``key`` (runtime.goal_client): ``send(goal,
        on_feedback=...)`` returns a future of the result, ``cancel()`` cancels the running goal.
        It holds a caller token while it is declared: its goals end if this node goes away.  It
        follows the graph's tokens of the service's servers: when the last one goes away (its
        node exits, its host is cut off) the node logs it once and the running goals end
        (``GoalFailed`` naming it); when one is back, it logs that once."""
        core = self.core

        def build(declared: Declaration) -> GoalClient[G, F, R]:
            client_id = f"{core.name.replace('/', '.')}.{os.getpid()}.{next(_client_ids)}"
            declared.add(core.session.liveliness().declare_token(client_token(client_id)))
            client = GoalClient(self, declared, key, (goal_type, feedback_type, result_type), client_id)

            def on_token(sample: zenoh.Sample) -> None:  # Zenoh thread: hand over only
                entity = parse_entity_token(str(sample.key_expr))
                if entity is not None and entity.role == "goal" and entity.key == declared.key:
                    alive = sample.kind == zenoh.SampleKind.PUT
                    core.enqueue(client.server_seen, alive, entity.node, entity.pid)

            servers = (
                f"{ENTITY_TOKEN_PREFIX}/*/*/goal/*/{declared.key}"  # the runtime's own graph: not the node's interface
            )
            declared.add(core.session.liveliness().declare_subscriber(servers, on_token, history=True))
            return client

        return core.declare(GOAL_CLIENT, key, (), build)
