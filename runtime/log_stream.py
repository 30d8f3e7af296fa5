"""One log stream: every record a node process logs is also published on the node's log key,
``turtlectl/log/<node>`` (a ``Log`` each: level, node, message, source line, when), as ROS
nodes publish theirs on ``/rosout``; the node also answers a get on that key with its last
``RECENT`` records, so ``turtlectl log`` can show what was logged before it started.

``LogStream`` is a ``logging.Handler`` on the root logger, installed by ``runtime.lifecycle``
once the node's session is open and removed before it closes: records from before (a bad
configuration, no router) and after are in the process's stderr only (the launch output and
its log file).  It takes what the node's log level lets through, from any thread (Zenoh's
included): a record is encoded and kept under a lock and published outside it (a Zenoh put
from any thread is fine).  A record never fails the logging call: a publish that raises is
dropped, and a record logged while this thread is publishing one (Zenoh, or anything it
calls, logging) is not published again.

``runtime.fake.FakeNode`` installs none: a node class's unit test sees only what it publishes.
"""

from __future__ import annotations

import collections
import logging
import threading
from typing import TYPE_CHECKING, Any

import zenoh

from turtlectl.messages import Log, encode
from turtlectl.messages.keys import log_key
from turtlectl.runtime.entities import sample_encoding

if TYPE_CHECKING:
    from turtlectl.runtime.node import Node

#: records a node keeps for a get on its log key (``turtlectl log`` without --follow)
RECENT = 200

_TRACEBACKS = logging.Formatter()  # formats a record's exception and stack as logging's own lines do


def text_of(record: logging.LogRecord) -> str:
    """A record's message as its log line shows it, with its traceback and stack when it has
    them (arguments that do not fit the format: the format and the arguments as they are)."""
    try:
        text = record.getMessage()
    except (TypeError, ValueError):
        text = f"{record.msg} {record.args}"
    if record.exc_info and not record.exc_text:
        record.exc_text = _TRACEBACKS.formatException(record.exc_info)
    if record.exc_text:
        text = f"{text}\n{record.exc_text}"
    if record.stack_info:
        text = f"{text}\n{_TRACEBACKS.formatStack(record.stack_info)}"
    return text


def to_log(record: logging.LogRecord, node: str, seq: int = 0) -> Log:
    """The wire form of ``record``, logged in node ``node``."""
    return Log(
        level=record.levelno,
        node=node,
        message=text_of(record),
        file=record.pathname or "",
        function=record.funcName or "",
        line=record.lineno or 0,
        stamp=round(record.created * 1e9),
        seq=seq,
    )


class LogStream(logging.Handler):
    """Publishes each record that reaches the root logger on ``node``'s log key and keeps the
    last ``recent`` for a get on it (``close`` withdraws both)."""

    def __init__(self, node: Node[Any], recent: int = RECENT):
        super().__init__()  # NOTSET: the node's log level (the root logger's) decides what comes here
        self.node_name = node.name
        self.key = log_key(node.name)
        self._encoding = sample_encoding(Log)
        self._recent: collections.deque[bytes] = collections.deque(maxlen=recent)  # encoded, oldest first
        self._seq = 0
        self._kept = threading.Lock()  # the ring and the sequence number
        self._publishing = threading.local()  # this thread is inside a publish: what it logs is not published
        self.closed = False
        session = node.session
        self._publisher = session.declare_publisher(
            self.key, encoding=self._encoding, congestion_control=zenoh.CongestionControl.DROP
        )
        self._queryable = session.declare_queryable(self.key, self._on_query)
        self._token = node.core.announce("pub", Log, self.key)  # `turtlectl list --all` shows it, tools learn its type
        node.core.uses(Log)

    def handle(self, record: logging.LogRecord) -> bool:  # type: ignore[override]
        """``emit`` without logging's lock around it: the ring has its own, and a publish from
        several threads at once is fine."""
        if self.closed or getattr(self._publishing, "active", False) or not self.filter(record):
            return False
        self._publishing.active = True
        try:
            self.emit(record)
        finally:
            self._publishing.active = False
        return True

    def emit(self, record: logging.LogRecord) -> None:
        try:
            with self._kept:
                payload = encode(to_log(record, self.node_name, self._seq))
                self._seq += 1
                self._recent.append(payload)
            self._publisher.put(payload)
        except Exception:  # never into the logging call (a session closing, a payload refused)
            pass

    def _on_query(self, query: zenoh.Query) -> None:  # Zenoh thread: answer from a copy of the ring
        with self._kept:
            recent = list(self._recent)
        try:
            for payload in recent:
                query.reply(self.key, payload, encoding=self._encoding)
        except zenoh.ZError:  # the asker gave up, or the session is closing
            pass

    def close(self) -> None:
        """Stop publishing: off the root logger, the publisher, queryable and graph token
        withdrawn.  Idempotent (``logging.shutdown`` calls it too)."""
        if not self.closed:
            self.closed = True
            logging.getLogger().removeHandler(self)
            for entity in (self._token, self._queryable, self._publisher):
                try:
                    entity.undeclare()
                except zenoh.ZError:
                    pass
        super().close()


def start(node: Node[Any]) -> LogStream:
    """Publish every record this process logs from now on on ``node``'s log key."""
    stream = LogStream(node)
    logging.getLogger().addHandler(stream)
    return stream
