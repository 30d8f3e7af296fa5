"""Every declaration of a node returns a handle that can be undeclared: with a real
router, an undeclared subscription, service, liveliness watch, publisher or latest value stops
at once, its graph token goes, and what was queued before is not delivered."""

from __future__ import annotations

import pytest
import zenoh

from tests.integration.harness import node_in_process
from tests.integration.test_runtime import _until
from turtlectl.messages import Ack, ErrorReply, Pose, Reset, decode, encode
from turtlectl.messages.keys import ENTITY_TOKEN_PREFIX, parse_entity_token
from turtlectl.runtime.node import Node

pytestmark = pytest.mark.integration


@pytest.fixture
def node_and_client():
    with node_in_process("handles") as pair:
        yield pair


def run_queued(node: Node) -> None:
    """What the node's thread does with what was queued for it."""
    node.core.drain()


def _try(check) -> bool:
    """``check()``, an assertion in it counting as not yet."""
    try:
        return check()
    except AssertionError:
        return False


def graph(client: zenoh.Session) -> set[tuple[str, str]]:
    """(role, key) of every entity token of the node named handles."""
    replies = client.liveliness().get(f"{ENTITY_TOKEN_PREFIX}/**", timeout=2.0)
    found = set()
    for reply in replies:
        if reply.ok is not None:
            info = parse_entity_token(str(reply.ok.key_expr))
            if info is not None and info.node == "handles":
                found.add((info.role, info.key))
    return found


def test_an_undeclared_subscription_delivers_nothing_more_not_even_what_was_queued(node_and_client):
    node, client = node_and_client
    seen: list[float] = []
    sub = node.subscribe("test/handles/pose", Pose, lambda p: seen.append(p.x))
    pub = client.declare_publisher("test/handles/pose")
    _until(lambda: seen, act=lambda: (pub.put(encode(Pose(x=1.0, y=0.0, theta=0.0))), run_queued(node)))
    _until(lambda: ("sub", "test/handles/pose") in graph(client))
    pub.put(encode(Pose(x=2.0, y=0.0, theta=0.0)))
    _until(lambda: node.core.pending())  # queued, not yet run
    sub.undeclare()
    seen.clear()
    run_queued(node)
    pub.put(encode(Pose(x=3.0, y=0.0, theta=0.0)))
    assert seen == [] and node.core.pending() == 0
    _until(lambda: ("sub", "test/handles/pose") not in graph(client))
    sub.undeclare()  # twice: nothing more


def test_an_undeclared_service_is_gone_and_a_query_queued_before_gets_an_error(node_and_client):
    node, client = node_and_client
    calls: list[str] = []

    def handler(request):
        calls.append("called")
        request.respond(Ack())

    service = node.serve("test/handles/reset", Reset, Ack, handler)
    _until(lambda: ("srv", "test/handles/reset") in graph(client))

    def answered() -> bool:  # a first query answered: the service is known at the router
        replies = client.get("test/handles/reset", payload=encode(Reset()), timeout=1.0)
        _try(lambda: _until(lambda: calls, act=lambda: run_queued(node), timeout=0.5))
        return any(r.ok is not None for r in replies)

    _until(answered)
    calls.clear()
    replies = client.get("test/handles/reset", payload=encode(Reset()), timeout=2.0)
    _until(lambda: node.core.pending())
    service.undeclare()
    run_queued(node)
    answers = list(replies)
    assert calls == [] and len(answers) == 1 and answers[0].err is not None
    assert "no longer served" in decode(answers[0].err.payload.to_bytes(), ErrorReply).error
    assert list(client.get("test/handles/reset", payload=encode(Reset()), timeout=0.5)) == []
    assert ("srv", "test/handles/reset") not in graph(client)


def test_undeclared_watch_publisher_and_latest_value(node_and_client):
    node, client = node_and_client
    events: list[tuple[str, bool]] = []
    watch = node.watch_liveliness("test/handles/alive/**", lambda key, alive: events.append((key, alive)))
    tokens = []

    def announce() -> None:  # a new token each time: the watch may not have reached the router yet
        tokens.append(client.liveliness().declare_token(f"test/handles/alive/{len(tokens)}"))
        run_queued(node)

    _until(lambda: events, act=announce)
    watch.undeclare()
    seen = list(events)
    for token in tokens:
        token.undeclare()
    announce()
    run_queued(node)
    assert events == seen and all(alive for _, alive in seen)

    got: list[bytes] = []
    listener = client.declare_subscriber("test/handles/out", lambda s: got.append(s.payload.to_bytes()))
    pub = node.publisher("test/handles/out", Pose)
    _until(lambda: got, act=lambda: pub.publish(Pose(x=1.0, y=0.0, theta=0.0)))
    pub.undeclare()
    _until(lambda: ("pub", "test/handles/out") not in graph(client))
    listener.undeclare()

    latest = node.latest("test/handles/in", Pose)
    source = client.declare_publisher("test/handles/in")
    _until(lambda: latest.get(), act=lambda: source.put(encode(Pose(x=5.0, y=0.0, theta=0.0))))
    latest.undeclare()
    source.put(encode(Pose(x=6.0, y=0.0, theta=0.0)))
    _until(lambda: ("sub", "test/handles/in") not in graph(client))
    assert latest.get().x == 5.0  # the last one kept, nothing after
