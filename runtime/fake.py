"""A node class unit-tested without Zenoh, as dora's ``MockNode`` or ROS's ``launch_testing``
do: ``FakeNode(MyNode, {"side": 2.0})`` runs the real ``runtime.node.Node`` code over an
in-memory session (``FakeSession``) and a fake clock, so the test delivers messages and
requests, moves time on so timers fire, and reads what the node published and answered::

    fake = FakeNode(Patrol, {"side": 2.0})
    fake.deliver("turtle1/pose", Pose(x=1.0, y=1.0, theta=0.0))
    fake.advance(0.35)  # a 0.1 s timer: three ticks, each at its own deadline
    assert fake.published("turtle1/cmd_vel")[-1].linear > 0

Messages travel encoded (``messages.encode``), as on the wire, so the node's decoding and
its handling of garbage (``deliver(key, b"...")``) run as in production.  Everything runs on
the test's thread, at once: each method runs what it queued before it returns, and an
exception raised by node code reaches the test.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Generic, TypeVar

import msgspec

from turtlectl.messages import Cancel, Message, SetParameter, decode_any, encode
from turtlectl.messages.keys import client_token, param_set_key
from turtlectl.messages.world import Limits, World
from turtlectl.runtime.config import Interface, NodeConfig
from turtlectl.runtime.entities import sample_encoding
from turtlectl.runtime.fake_session import JSON, FakeSession, RawReplies
from turtlectl.runtime.node import Node, P
from turtlectl.runtime.roles import interface_of

__all__ = ["FakeGoal", "FakeNode", "FakeSession", "unstamped"]

M = TypeVar("M", bound=msgspec.Struct)
_EPSILON = 1e-9  # s: a deadline this close to where ``advance`` stops is reached (float rounding)


def unstamped(message: M) -> M:
    """``message`` with ``stamp`` and ``seq`` back at 0, so that it equals the message the node
    code built: a publisher fills both in as it sends (the node's time in ns, its count), so
    ``fake.published(key)[-1] == Twist(linear=1.0)`` never holds, and
    ``unstamped(fake.published(key)[-1]) == Twist(linear=1.0)`` does.  A message without both
    fields (the publisher stamps only those with both) comes back as it is; so do the messages
    inside it (what the node built, stamps included)."""
    fields = message.__struct_fields__
    if "stamp" in fields and "seq" in fields:
        return msgspec.structs.replace(message, stamp=0, seq=0)
    return message


def _decoded(data: bytes, encoding: Any) -> Any:
    """A reply as the test reads it: a message (an error as ``ErrorReply``), or a JSON answer's
    document (``answer_json``: parameters, node details)."""
    if encoding is not None and str(encoding) == str(JSON):
        return msgspec.json.decode(data)
    return decode_any(data)


class _Replies(list[Any]):
    """The decoded replies of one request, growing as the handler answers (later ones too)."""

    def __init__(self, raw: RawReplies):
        super().__init__()
        self._raw = raw

    @property
    def ended(self) -> bool:
        """Whether the call ended (its final reply came: a goal's result)."""
        return self._raw.ended

    def refresh(self) -> _Replies:
        for data, encoding in self._raw[len(self) :]:
            self.append(_decoded(data, encoding))
        return self


def _snake(name: str) -> str:
    """``WallFollower`` -> ``wall_follower`` (a class's name as its node's, as ``turtlectl run``)."""
    return "".join(f"_{c.lower()}" if c.isupper() and i else c.lower() for i, c in enumerate(name))


class FakeNode(Generic[P]):
    """``node_class`` built on a real ``Node`` over a ``FakeSession`` and a fake clock.

    ``params``: None (the defaults), a dict (validated as a launch file's, ValueError if it is
    not valid) or the ``node_class.Params`` Struct itself.  ``name``: the node's, by default
    the class's in snake case (a full name, ``turtle2/patrol``, puts it in a namespace); ``remaps``:
    its launch file's ``remap``.  ``.node`` is the ``Node``, ``.instance`` the node class's
    object, ``.now`` the fake time in s (0.0 at the start).  A context manager: ``shutdown``
    on exit."""

    def __init__(
        self,
        node_class: Callable[[Node[P]], Any],
        params: P | dict[str, Any] | None = None,
        *,
        name: str | None = None,
        world: World | None = None,
        limits: Limits | None = None,
        remaps: dict[str, str] | None = None,
    ):
        params_type = getattr(node_class, "Params", None)
        struct = _params(node_class, params_type, params)
        self.now = 0.0
        self.session = FakeSession()
        self._pending: list[_Replies] = []  # every request's replies, refreshed as the node runs
        name = name or _snake(getattr(node_class, "__name__", "node"))
        declared = getattr(node_class, "Interface", None)
        config = NodeConfig(
            name=name,
            kind=getattr(node_class, "__name__", "node"),
            connect="fake",
            params=msgspec.to_builtins(struct),
            # what it may declare, as in a launched system: a declaration outside it raises here too
            interface=interface_of(name, declared if isinstance(declared, Interface) else None, remaps),
            remaps=remaps or {},
            world=world or World(),
            limits=limits or Limits(),
        )
        self.node: Node[P] = Node(config, struct, self.session, clock=self._clock)  # type: ignore[arg-type]
        self.instance = node_class(self.node)
        self._ran()

    def _clock(self) -> float:
        return self.now

    # -- what happens to the node --------------------------------------------
    def deliver(self, key: str, message: Message | bytes) -> None:
        """``message`` arrives on ``key`` (bytes: a raw payload, garbage included); what it
        queued runs."""
        if isinstance(message, bytes):
            self.session.deliver(key, message)
        else:
            self.session.deliver(key, encode(message), sample_encoding(type(message)))
        self._ran()

    def request(self, key: str, request: Message | bytes | None = None, attachment: bytes | None = None) -> list[Any]:
        """Call the node's service ``key`` with ``request`` (bytes: a raw payload; None: no
        payload): its replies so far, decoded (an error reply as ``ErrorReply``, a JSON answer
        as its document; none: nobody serves ``key``).  The list grows with replies sent
        later (a goal's feedback and result, after ``advance``); ``attachment``: the query's."""
        if request is None or isinstance(request, bytes):
            raw = self.session.query(key, request, attachment=attachment)
        else:
            raw = self.session.query(key, encode(request), sample_encoding(type(request)), attachment)
        replies = _Replies(raw)
        self._pending.append(replies)
        self._ran()
        return replies.refresh()

    def _ran(self) -> None:
        self.node.core.drain()
        for replies in self._pending:
            replies.refresh()

    def advance(self, seconds: float) -> None:
        """Move the fake clock ``seconds`` on, firing each timer due meanwhile at its own
        deadline, in order, and running what it queued, as the node's loop would (its core's
        ``fire_due`` and ``drain``, deadline by deadline)."""
        if seconds < 0:
            raise ValueError(f"the clock only moves forward (advance({seconds}))")
        until = self.now + seconds
        core = self.node.core
        self._ran()
        while True:
            deadline = core.next_deadline()
            if deadline is None or deadline > until + _EPSILON:
                break
            self.now = max(self.now, deadline)
            core.fire_due(self.now)
            self._ran()
        self.now = max(self.now, until)

    def send_goal(self, key: str, goal: Message, client: str = "caller") -> FakeGoal:
        """Send ``goal`` to the node's goal service ``key`` (``Node.goal_server``), as a caller
        holding the token ``@turtlectl/client/<client>`` (named by the query's attachment):
        its ``feedback`` and ``result`` grow as the node runs (``advance``)."""
        self.liveliness(client_token(client), True)
        return FakeGoal(self, key, self.request(key, goal, attachment=client.encode()), client)

    def answer(self, key: str, fn: Callable[[Message], list[Message]]) -> None:
        """What a service the node calls (``Node.call``) on ``key`` answers: ``fn(request)``'s
        messages.  A key nothing answers: the call is done at once, with no replies."""
        self.session.answers[key] = fn

    def liveliness(self, key: str, alive: bool) -> None:
        """A liveliness token ``key`` appears (``alive``) or vanishes (``watch_liveliness``)."""
        self.session.token(key, alive)
        self._ran()

    def set_param(self, name: str, value: Any) -> Message:
        """``turtlectl param set``, through the node's own service: its ``Ack``, or the
        ``ErrorReply`` saying why not."""
        replies = self.request(param_set_key(self.node.name), SetParameter(name=name, value=value))
        if not replies:
            raise RuntimeError(f"{self.node.name} did not answer its parameter set")
        reply: Message = replies[0]
        return reply

    def shutdown(self) -> None:
        """Stop the node: its shutdown hooks run (once)."""
        self.node.shutdown()
        self._ran()

    # -- what the node did ----------------------------------------------------
    def published(self, key: str) -> list[Message]:
        """The messages the node published on ``key``, decoded, oldest first, each stamped by
        its publisher (``unstamped(msg)`` compares it with a message built by hand)."""
        return [decode_any(data) for k, data in self.session.published if k == key]

    def published_all(self) -> list[tuple[str, Message]]:
        """Every message the node published, as (key, message), oldest first."""
        return [(k, decode_any(data)) for k, data in self.session.published]

    def __enter__(self) -> FakeNode[P]:
        return self

    def __exit__(self, *_: object) -> None:
        self.shutdown()


class FakeGoal:
    """A goal sent to a node under test (``FakeNode.send_goal``): what came back so far."""

    def __init__(self, fake: FakeNode[Any], key: str, replies: _Replies, client: str):
        self.key, self.client = key, client
        self._fake = fake
        self._replies = replies

    @property
    def replies(self) -> list[Any]:
        """Every reply so far, decoded, oldest first: feedback, then the result."""
        return list(self._replies.refresh())

    @property
    def feedback(self) -> list[Any]:
        """The feedback replies so far, oldest first."""
        replies = self.replies
        return replies[:-1] if self._replies.ended else replies

    @property
    def result(self) -> Any:
        """The goal's result (a refused goal's too); None while it runs."""
        replies = self.replies
        return replies[-1] if self._replies.ended and replies else None

    def cancel(self, reason: str = "") -> Message:
        """``KEY/cancel``, as ``turtlectl cancel`` asks: the server's ``Ack``."""
        replies = self._fake.request(f"{self.key}/cancel", Cancel(reason=reason))
        if not replies:
            raise RuntimeError(f"nothing serves {self.key}/cancel")
        answer: Message = replies[0]
        return answer

    def caller_gone(self) -> None:
        """The caller goes away (Ctrl-C, killed): its liveliness token vanishes."""
        self._fake.liveliness(client_token(self.client), False)


def _params(node_class: Any, params_type: Any, params: Any) -> msgspec.Struct:
    """The node's parameter Struct from what the test gave (ValueError if it is not valid)."""
    shown = getattr(node_class, "__name__", repr(node_class))
    if isinstance(params, msgspec.Struct):
        if params_type is not None and not isinstance(params, params_type):
            raise ValueError(f"{shown} takes {params_type.__name__} params, not {type(params).__name__}")
        return params
    if not (isinstance(params_type, type) and issubclass(params_type, msgspec.Struct)):
        raise ValueError(f"{shown} is not a node class: it has no Params (its parameter msgspec.Struct)")
    if params is not None and not isinstance(params, dict):
        raise ValueError(f"params for {shown}: a dict or a {params_type.__name__}, not {type(params).__name__}")
    try:
        return msgspec.convert(params or {}, params_type, strict=True)
    except msgspec.ValidationError as exc:
        raise ValueError(f"invalid params for {shown}: {exc}") from None
