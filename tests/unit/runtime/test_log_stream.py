"""runtime.log_stream: every record a node process logs at its level is also published on its
log key, from any thread, and its last ones are answered to a get; a failing publish or a
publish that logs never reaches the logging call; a closed stream publishes nothing."""

from __future__ import annotations

import logging
import sys
import threading
from types import SimpleNamespace
from typing import Any

import pytest

from turtlectl.messages import Log, decode
from turtlectl.messages.keys import log_key
from turtlectl.runtime import log_stream
from turtlectl.runtime.log_stream import LogStream, to_log


class Entity:
    def __init__(self, key: str, callback: Any = None):
        self.key, self.callback, self.undeclared = key, callback, False
        self.put_hook: Any = None
        self.sent: list[bytes] = []

    def put(self, payload: bytes) -> None:
        if self.put_hook is not None:
            self.put_hook()
        self.sent.append(payload)

    def undeclare(self) -> None:
        self.undeclared = True


class Session:
    """What LogStream uses of a zenoh.Session."""

    def __init__(self) -> None:
        self.publishers: list[Entity] = []
        self.queryables: list[Entity] = []

    def declare_publisher(self, key: str, **_: Any) -> Entity:
        self.publishers.append(Entity(key))
        return self.publishers[-1]

    def declare_queryable(self, key: str, callback: Any) -> Entity:
        self.queryables.append(Entity(key, callback))
        return self.queryables[-1]


class Query:
    def __init__(self) -> None:
        self.replies: list[tuple[str, bytes]] = []

    def reply(self, key: str, payload: bytes, encoding: Any = None) -> None:
        self.replies.append((key, payload))


def fake_node(name: str = "turtle2/navigator") -> SimpleNamespace:
    used: list[type] = []
    announced: list[tuple[str, Any, str]] = []
    return SimpleNamespace(
        name=name,
        session=Session(),
        core=SimpleNamespace(
            announce=lambda role, msg_type, key: announced.append((role, msg_type, key)) or Entity(key),
            uses=used.append,
        ),
        used=used,
        announced=announced,
    )


@pytest.fixture
def node():
    """A node whose stream is on the root logger (at INFO) for the test, and off it after."""
    root = logging.getLogger()
    level = root.level
    root.setLevel(logging.INFO)
    made = fake_node()
    made.stream = log_stream.start(made)
    yield made
    made.stream.close()
    root.setLevel(level)


def sent(node: SimpleNamespace) -> list[Log]:
    (publisher,) = node.session.publishers
    return [decode(p, Log) for p in publisher.sent]


def test_each_record_at_the_nodes_level_is_published_on_its_log_key(node):
    log = logging.getLogger("turtle2/navigator")
    log.debug("not at the node's level")
    log.info("goal (%g, %g)", 8, 5)
    logging.getLogger("runtime").warning("lost the router")  # any logger of the process
    got = sent(node)
    assert [(r.level, r.node, r.message, r.seq) for r in got] == [
        (20, "turtle2/navigator", "goal (8, 5)", 0),
        (30, "turtle2/navigator", "lost the router", 1),
    ]
    assert (
        got[0].file == __file__ and got[0].function == "test_each_record_at_the_nodes_level_is_published_on_its_log_key"
    )
    assert got[0].line > 0 and got[0].stamp <= got[1].stamp
    (publisher,) = node.session.publishers
    assert publisher.key == log_key("turtle2/navigator") == "turtlectl/log/turtle2.navigator"
    assert node.announced[0][:2] == ("pub", Log) and Log in node.used  # in the graph; its type described


def test_a_record_with_a_traceback_carries_it():
    try:
        raise ValueError("bad value")
    except ValueError:
        made = logging.LogRecord("n", logging.ERROR, __file__, 1, "failed while starting", (), sys.exc_info())
    wire = to_log(made, "sim")
    assert wire.message.startswith("failed while starting\nTraceback (most recent call last):")
    assert wire.message.endswith("ValueError: bad value")


def test_a_message_whose_arguments_do_not_fit_is_kept_as_it_came():
    made = logging.LogRecord("n", logging.INFO, __file__, 1, "%d goals", ("many",), None)
    assert to_log(made, "sim").message == "%d goals ('many',)"


def test_records_from_other_threads_are_published_too(node):
    threads = [
        threading.Thread(target=lambda i=i: logging.getLogger("zenoh-thread").info("from thread %d", i))
        for i in range(8)
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    got = sent(node)
    assert sorted(r.message for r in got) == sorted(f"from thread {i}" for i in range(8))
    assert sorted(r.seq for r in got) == list(range(8))  # each its own number


def test_a_failing_publish_never_reaches_the_logging_call(node):
    (publisher,) = node.session.publishers

    def fail() -> None:
        raise RuntimeError("session closed")

    publisher.put_hook = fail
    logging.getLogger("x").error("still fine for the caller")  # no exception here
    publisher.put_hook = None
    logging.getLogger("x").info("and the next one goes out")
    assert [r.message for r in sent(node)] == ["and the next one goes out"]


def test_a_publish_that_logs_is_not_published_again(node):
    (publisher,) = node.session.publishers
    publisher.put_hook = lambda: logging.getLogger("zenoh").warning("congestion")  # logged while publishing
    logging.getLogger("x").info("one record")
    assert [r.message for r in sent(node)] == ["one record"]


def test_a_get_is_answered_with_the_last_records_oldest_first():
    root = logging.getLogger()
    level = root.level
    root.setLevel(logging.INFO)
    made = fake_node("sim")
    stream = LogStream(made, recent=3)
    root.addHandler(stream)
    try:
        for i in range(5):
            logging.getLogger("sim").info("record %d", i)
        (queryable,) = made.session.queryables
        query = Query()
        queryable.callback(query)
        assert {key for key, _ in query.replies} == {"turtlectl/log/sim"}
        assert [decode(p, Log).message for _, p in query.replies] == ["record 2", "record 3", "record 4"]
    finally:
        stream.close()
        root.setLevel(level)


def test_a_closed_stream_publishes_nothing_and_withdraws_what_it_declared(node):
    node.stream.close()
    logging.getLogger("x").warning("after the session")
    assert sent(node) == []
    assert node.stream not in logging.getLogger().handlers
    assert all(e.undeclared for e in (*node.session.publishers, *node.session.queryables))
    node.stream.close()  # idempotent
