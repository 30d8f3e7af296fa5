"""Where ``turtlectl plot``'s numbers come from: a recording read whole (``from_recording``), or
a running system, sample by sample as they arrive (``Live``).  Nothing here prints; errors are
TurtlectlErrors (runtime.client.errors): a field that is not a number is BadInput (exit 2), a key a
recording does not hold, or no number at all, Unreachable (exit 3)."""

from __future__ import annotations

import dataclasses
import queue
import time
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import zenoh

from turtlectl.cli.tools.format import Undescribed
from turtlectl.cli.tools.plot import Extractor, Series, Stamps, check_stamped, check_type, nearest_key
from turtlectl.cli.tools.plot_window import Collected
from turtlectl.cli.tools.rates import Quiet
from turtlectl.cli.tools.routerwatch import watch
from turtlectl.cli.tools.topics import silence_reason
from turtlectl.messages import Message
from turtlectl.messages.codec import TYPES_BY_NAME
from turtlectl.runtime.client import presence
from turtlectl.runtime.client.errors import Unreachable
from turtlectl.runtime.client.graph import Graph
from turtlectl.runtime.client.samples import Received, decode_sample, learn
from turtlectl.runtime.client.session import domain_of, live_graph
from turtlectl.runtime.client.typebook import TypeBook, generic


@dataclasses.dataclass
class FromRecording:
    """A recording's numbers (``collected``: times in s from the recording's start), and
    whether the recorder closed the file (one that was not is read as far as it is whole)."""

    collected: Collected
    closed: bool
    duration: float  # s, the whole recording's


def from_recording(path: Path, series: list[Series], stamps: bool = False) -> FromRecording:
    """Every number of each series in the recording at ``path``, on the time of its log (when
    the recorder received each message) from the recording's first message; with ``stamps``,
    on each message's own stamp from the earliest (messages not stamped left out).  RecordingError
    (exit 2) for a file that is no recording, BadInput (exit 2) for a field that is no number
    (checked against the type the file holds), Unreachable (exit 3) for a key the file does
    not hold or no number at all."""
    from turtlectl.cli.recording.reading import Recording

    recording = Recording(path)
    info = recording.info()
    # a ROS 2 bag's topics are ROS names (/turtle1/pose): plotted by their keys (turtle1/pose)
    held = {t.key[1:] if t.key.startswith("/") else t.key: t for t in info.topics if t.count}
    extractor = Extractor(series)
    keys = list(extractor.by_key)
    missing = [k for k in keys if k not in held]
    if missing:
        holds = ", ".join(sorted(held)) or "no message at all"
        raise Unreachable(f"{path} has no messages on {', '.join(missing)} (it holds {holds})")
    types: dict[str, type[Message]] = {}
    for s in series:
        msg_type = TYPES_BY_NAME.get(held[s.key].type_name)
        if msg_type is not None:
            check_type(s, msg_type)
            types[s.key] = msg_type
    if stamps:
        check_stamped(types)  # BadInput for a type with no stamp
    collected = Collected(series)
    stamped = Stamps() if stamps else None
    for record in recording.records(keys):
        if record.scene:
            continue
        message: Any = record.message()
        key = record.key
        if message is None:  # kept raw: what it is, if it reads as data (a ROS 2 bag's CDR: by its .msg)
            ros = record.encoding == "cdr" and key.startswith("/")
            data = recording.ros_fields(record) if ros else generic(record.data, record.encoding)
            if data is None:
                continue
            message, key = Undescribed(data), key[1:] if ros else key
        t = (record.log_time - info.start) / 1e9 if stamped is None else stamped.time(key, message)
        if t is None:
            continue
        for s, value in extractor.values(key, message):
            collected.add(s, t, value)
    if not collected.count:
        labels = ", ".join(s.label for s in series)
        also = ", messages not stamped (--stamps)" if stamps else ""
        raise Unreachable(
            f"{path}: no number to plot in {labels} (only inf or NaN{also}, or payloads that are no message)"
        )
    return FromRecording(collected, recording.closed, info.duration if stamped is None else collected.rebase())


def typo_notes(graph: Graph, series: list[Series], turtle: str = "") -> dict[str, str]:
    """For each key that is no built-in one and that nothing in ``graph`` publishes, but near a
    built-in key (a typo: ``turtle1/pos``): key -> ``nothing publishes turtle1/pos: did you mean turtle1/pose?``."""
    return _typo_notes(graph, _nearest(dict.fromkeys(s.key for s in series), turtle))


def _nearest(keys: Iterable[str], turtle: str) -> dict[str, str]:
    """Each key near a built-in one (but none itself) -> that built-in key."""
    return {key: near for key in keys if (near := nearest_key(key, turtle))}


def _typo_notes(graph: Graph, nearest: dict[str, str]) -> dict[str, str]:
    notes = {}
    for key, near in nearest.items():
        expr = zenoh.KeyExpr(key)
        if not any(t.publishers and expr.intersects(zenoh.KeyExpr(t.key)) for t in graph.topics):
            notes[key] = f"nothing publishes {key}: did you mean {near}?"
    return notes


def _quiet_from(now: float, before: Quiet) -> Quiet:
    """``before`` counting its silence from ``now`` (whether messages flowed is kept)."""
    quiet = Quiet(now)
    quiet.flowed = before.flowed
    return quiet


class Live:
    """A running system's numbers as they arrive: ``poll`` gives the samples since the last
    call (times in s since this started); ``notices`` say why a key is silent; ``said`` the
    router lost and back, a line each (cli.tools.routerwatch: the caller prints and clears it;
    ``router`` says it while it lasts, for a status line; ``exit_on_loss``: RouterLost instead).  Decoding and type learning as echo's
    (a user's own type is learnt from the nodes that use it)."""

    def __init__(
        self,
        session: zenoh.Session,
        connect: str,
        series: list[Series],
        stamps: bool = False,
        turtle: str = "",
        exit_on_loss: bool = False,
    ):
        self.session = session
        self.connect = connect
        self.extractor = Extractor(series)
        self.keys = list(self.extractor.by_key)
        self.inbox: queue.SimpleQueue[tuple[float, Received]] = queue.SimpleQueue()
        self.book = TypeBook(session)
        self.started = time.monotonic()
        self.quiet = {key: Quiet(self.started) for key in self.keys}
        self.silent: dict[str, str] = {}  # key -> why it is silent
        self.router = ""  # why there is no router ("" while there is one)
        self.said: list[str] = []  # the router lost, back: a line each, for the caller to print
        self._router = watch(session, connect, f"messages on {', '.join(self.keys)}", exit_on_loss)
        self.received = 0  # numbers so far
        self.stamps = Stamps() if stamps else None  # --stamps: the time axis is the messages' stamps
        self.typos: dict[str, str] = {}  # key -> "did you mean" (a key near a built-in one nobody publishes)
        nearest = _nearest(self.keys, turtle)
        if nearest:
            self.typos = _typo_notes(live_graph(session), nearest)
        self._subs = [presence.subscriber(session, key, self._on_sample) for key in self.keys]

    def _on_sample(self, sample: zenoh.Sample) -> None:  # Zenoh's thread: decode and queue
        received = decode_sample(str(sample.key_expr), sample.payload.to_bytes(), str(sample.encoding))
        self.inbox.put((time.monotonic(), received))

    def close(self) -> None:
        for sub in self._subs:
            sub.undeclare()
        self._subs = []

    def elapsed(self) -> float:
        """Seconds since this started (the time axis)."""
        return time.monotonic() - self.started

    @property
    def notices(self) -> list[str]:
        """What to tell the user now: the router lost, the keys silent and why."""
        return list(self.silent.values())

    def poll(self, wait: float = 0.0) -> list[tuple[Series, float, float]]:
        """The samples (series, s since the start, number) that arrived since the last call,
        after waiting up to ``wait`` s for the first.  BadInput (exit 2) when the first
        message of a series has no number at its field."""
        found: list[tuple[Series, float, float]] = []
        deadline = time.monotonic() + wait
        while True:
            try:
                arrived, item = self.inbox.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                break
            found += self._samples(arrived, item)
            deadline = 0.0  # the rest without waiting
        self._watch(time.monotonic())
        self.received += len(found)
        return found

    def _samples(self, arrived: float, item: Received) -> list[tuple[Series, float, float]]:
        key = item.key
        if key in self.quiet:
            self.quiet[key].heard(arrived)
            self.silent.pop(key, None)
        item = learn(item, self.book)
        message: Any = item.message
        if message is None and item.generic is not None:
            message = Undescribed(item.generic, item.unknown)
        if message is None:
            return []
        t = arrived - self.started if self.stamps is None else self.stamps.time(key, message)
        if t is None:  # not stamped
            return []
        return [(s, t, value) for s, value in self.extractor.values(key, message)]

    def why_silent(self) -> str:
        """Why nothing has arrived on the keys that had no message (as echo says it), asked now."""
        graph = live_graph(self.session)
        return "; ".join(self._silence(key, graph) for key, quiet in self.quiet.items() if not quiet.flowed)

    def _silence(self, key: str, graph: Graph, flowed: bool = False) -> str:
        """Why ``key`` is silent (as echo says it), with "did you mean" for a key that looks like
        a typo of a built-in one."""
        why = silence_reason(key, graph, self.connect, domain_of(self.session), flowed)
        near = self.typos.get(key, "").partition(": ")[2]
        return f"{why.split(' (')[0]}: {near}" if near else why

    def _watch(self, now: float) -> None:
        if (line := self._router.check(now)) is not None:
            self.said.append(line)
            if not self._router.lost:  # silences count from the return
                self.quiet = {key: _quiet_from(now, quiet) for key, quiet in self.quiet.items()}
        lost = self._router.lost
        self.router = f"no router at {self.connect}: waiting for it (is `turtlectl launch` running?)" if lost else ""
        if lost:
            return
        due = [key for key, quiet in self.quiet.items() if quiet.due(now)]
        if due:  # the graph asked once (a liveliness query: up to 2 s), only when a key is due
            graph = live_graph(self.session)
            for key in due:
                self.silent[key] = self._silence(key, graph, self.quiet[key].flowed)
