"""What the page shows, kept as it arrives: one subscription to every key of the system (``**``,
a client subscriber listed in the graph), the newest pose, scan, goal feedback and status of each
turtle, each key's rate, the log records and the messages of the topics pages watch.

Samples arrive on Zenoh's threads; each updates the state under one lock, bumps ``version`` and
wakes the pages (``wake``: the server's, thread-safe).  A page takes what changed since the version
it last sent (``changes``), so a page that draws slower gets fewer frames, never a backlog.  Only
the types drawn, log records and the watched keys are decoded; every other sample is only counted.
"""

from __future__ import annotations

import collections
import threading
import time
from collections.abc import Callable
from typing import Any

import msgspec
import zenoh

from turtlectl.messages import LaserScan, Log, NavigateToFeedback, Pose, Turtles, TurtleStatus, type_from_encoding
from turtlectl.messages.keys import FEEDBACK, OBSTACLES, STATUS, turtle_of
from turtlectl.runtime.client import presence
from turtlectl.runtime.client.samples import decode_sample, learn
from turtlectl.runtime.client.typebook import TypeBook

RATE_WINDOW = 3.0  # s of arrivals a key's rate is measured over
LOG_KEEP = 1000  # log records kept for a page that connects later
GOAL_LIFETIME = 1.0  # s: a goal whose feedback stopped this long ago is no longer drawn running

DRAWN = (Pose, LaserScan, NavigateToFeedback, TurtleStatus, Turtles, Log)
KEPT = (Turtles, Log)  # decoded with no page open too: who is in the world, and the log a page shows from its start
_SUFFIXES = {f"/{OBSTACLES}": "scans", f"/{FEEDBACK}": "goals", f"/{STATUS}": "status"}


def turtle_and_section(key: str, type_name: str) -> tuple[str, str] | None:
    """Which turtle a drawn sample is about and the section it updates: ``turtle2/pose`` ->
    (turtle2, poses); ``navigate_to/feedback`` -> (turtle1, goals) (outside any namespace: turtle1's);
    ``turtle2/obstacles`` -> (turtle2, scans).  None for a key of another shape."""
    if type_name == "Pose" and key.count("/") == 1 and key.endswith("/pose"):
        return key.partition("/")[0], "poses"
    for suffix, section in _SUFFIXES.items():
        if f"/{key}".endswith(suffix):
            namespace = f"/{key}"[: -len(suffix)].strip("/")
            if "/" not in namespace:
                return turtle_of(namespace), section
    return None


def pose_fields(pose: Pose) -> dict[str, Any]:
    """A pose as the page draws it: m, m, rad, m/s, rad/s, contact, stamp (ns)."""
    return {
        "x": pose.x,
        "y": pose.y,
        "theta": pose.theta,
        "v": pose.linear_velocity,
        "w": pose.angular_velocity,
        "contact": pose.contact,
        "stamp": pose.stamp,
    }


def scan_fields(scan: LaserScan) -> dict[str, Any]:
    """A scan as the page draws it (rad, m; a beam that hit nothing is null)."""
    return {
        "angle_min": scan.angle_min,
        "angle_increment": scan.angle_increment,
        "range_max": scan.range_max,
        "ranges": scan.ranges,
        "origin": [scan.origin_x, scan.origin_y, scan.origin_theta],
    }


class Hub:
    """The state of every page: ``start`` subscribes on ``session``; ``close`` undeclares."""

    def __init__(self, session: zenoh.Session, wake: Callable[[], None], clock: Callable[[], float] = time.monotonic):
        self._session = session
        self._wake = wake
        self._clock = clock
        self._lock = threading.Lock()
        self.version = 0
        #: section -> turtle -> (version it changed at, fields)
        self._state: dict[str, dict[str, tuple[int, Any]]] = {s: {} for s in ("poses", "scans", "goals", "status")}
        self._arrivals: dict[str, collections.deque[float]] = {}
        self._types: dict[str, str] = {}  # key -> the type its samples' encoding names
        self._logs: collections.deque[tuple[int, dict[str, Any]]] = collections.deque(maxlen=LOG_KEEP)
        self._echo: dict[str, collections.deque[tuple[int, Any]]] = {}  # a watched key -> its recent messages
        self._watchers: collections.Counter[str] = collections.Counter()
        self._book = TypeBook(session)
        self._sub: Any = None
        self.turtles: list[str] = []  # the simulator's, as it last said
        self.skipped = 0  # samples of a drawn type that did not decode
        #: whether a page is open (the server says): with none, poses, scans, feedback and status are counted only
        self.viewed = True

    def start(self) -> None:
        handler = zenoh.handlers.Callback(self.on_sample, indirect=False)
        self._sub = presence.subscriber(self._session, "**", handler)

    def close(self) -> None:
        if self._sub is not None:
            self._sub.undeclare()
            self._sub = None

    # Zenoh's thread ------------------------------------------------------------------------------

    def on_sample(self, sample: zenoh.Sample) -> None:
        """One sample of the system (Zenoh's thread): counted; decoded and kept if drawn, a log record or watched."""
        key = str(sample.key_expr)
        now = self._clock()
        encoding = str(sample.encoding)
        msg_type = type_from_encoding(encoding)
        name = encoding.partition(";")[2]  # the type's full name, as the graph gives it (turtlectl/Pose)
        with self._lock:
            arrivals = self._arrivals.get(key)
            if arrivals is None:
                arrivals = self._arrivals[key] = collections.deque()
            arrivals.append(now)
            while arrivals and arrivals[0] < now - RATE_WINDOW:
                arrivals.popleft()
            self._types[key] = name
            watched = self._watchers[key] > 0
        if not watched and (msg_type not in DRAWN or (not self.viewed and msg_type not in KEPT)):
            return  # counted only: no page draws it now (a page that opens gets the next one)
        got = decode_sample(key, sample.payload.to_bytes(), encoding)
        if got.message is None and watched:
            got = learn(got, self._book)  # a user's type, described by the nodes that use it
        message = got.message
        with self._lock:
            self.version += 1
            version = self.version
            if watched:
                shown: Any = msgspec.to_builtins(message) if message is not None else got.generic
                if shown is None:
                    shown = {"problem": got.problem or "a payload no node describes"}
                self._echo.setdefault(key, collections.deque(maxlen=64)).append(
                    (version, {"key": key, "type": name, "message": shown})
                )
            if isinstance(message, Log):
                self._logs.append((version, log_fields(message)))
            elif isinstance(message, Turtles):
                self.turtles = list(message.names)
                for section in ("poses", "scans", "goals", "status"):
                    for gone in set(self._state[section]) - set(self.turtles):
                        self._state[section][gone] = (version, None)
            elif message is None:
                self.skipped += msg_type in DRAWN
            else:
                placed = turtle_and_section(key, type(message).__name__)
                if placed is not None:
                    turtle, section = placed
                    self._state[section][turtle] = (version, _fields(message, now))
        self._wake()

    # a page's view --------------------------------------------------------------------------------

    def changes(self, since: int) -> tuple[int, dict[str, dict[str, Any]]]:
        """The version now and, by section, each turtle's fields changed after ``since`` (None:
        the turtle is gone); a goal whose feedback stopped GOAL_LIFETIME s ago is None too."""
        now = self._clock()
        with self._lock:
            out: dict[str, dict[str, Any]] = {}
            for section, turtles in self._state.items():
                changed = {t: fields for t, (v, fields) in turtles.items() if v > since}
                if changed:
                    out[section] = changed
            for turtle, (_v, fields) in list(self._state["goals"].items()):
                if fields is not None and now - fields["received"] > GOAL_LIFETIME:
                    self.version += 1
                    self._state["goals"][turtle] = (self.version, None)
                    out.setdefault("goals", {})[turtle] = None
            return self.version, out

    def history(self, records: list[Log]) -> None:
        """The records the nodes held before the hub started (``turtlectl log``'s recent ones), put
        before those that came since (a record both held and heard is kept once)."""
        with self._lock:
            heard = {(r["node"], r["seq"], r["stamp"]) for _v, r in self._logs}
            older = [log_fields(r) for r in records if (r.node, r.seq, r.stamp) not in heard]
            self.version += 1
            kept = [(self.version, r) for r in older] + list(self._logs)  # a page has those heard already
            self._logs.clear()
            self._logs.extend(kept[-LOG_KEEP:])
        self._wake()

    def goal_running(self, turtle: str) -> bool:
        """Whether ``turtle``'s navigator sent feedback within GOAL_LIFETIME s (a goal runs)."""
        with self._lock:
            fields = self._state["goals"].get(turtle, (0, None))[1]
        return fields is not None and self._clock() - fields["received"] <= GOAL_LIFETIME

    def logs(self, since: int) -> tuple[int, list[dict[str, Any]]]:
        """Log records that arrived after version ``since``, oldest first, and the version to ask
        from next (the last one's)."""
        with self._lock:
            got = [(v, record) for v, record in self._logs if v > since]
        return max((v for v, _r in got), default=since), [record for _v, record in got]

    def echoes(self, keys: set[str], since: int) -> tuple[int, list[dict[str, Any]]]:
        """Messages on ``keys`` that arrived after version ``since``, oldest first, and the version to
        ask from next."""
        with self._lock:
            got = sorted(((v, m) for key in keys for v, m in self._echo.get(key, ()) if v > since), key=lambda i: i[0])
        return (got[-1][0] if got else since), [m for _v, m in got]

    def watch(self, added: set[str], removed: set[str]) -> None:
        """A page starts watching ``added`` and stops ``removed`` (counted: two pages, one key)."""
        with self._lock:
            self._watchers.update(added)
            self._watchers.subtract(removed)
            for key in removed:
                if self._watchers[key] <= 0:
                    del self._watchers[key]
                    self._echo.pop(key, None)

    def rates(self) -> dict[str, tuple[float, str]]:
        """Each key seen in the last RATE_WINDOW s: its rate (Hz) and the type its samples name."""
        now = self._clock()
        with self._lock:
            out = {}
            for key, arrivals in self._arrivals.items():
                while arrivals and arrivals[0] < now - RATE_WINDOW:
                    arrivals.popleft()
                if arrivals:  # over the arrivals of the window (a key that stopped leaves it within RATE_WINDOW s)
                    span = arrivals[-1] - arrivals[0]
                    out[key] = ((len(arrivals) - 1) / span if span > 0 else 0.0, self._types.get(key, ""))
            return out


def log_fields(record: Log) -> dict[str, Any]:
    """A log record as the page lists it."""
    return msgspec.to_builtins(record)


def _fields(message: Any, now: float) -> dict[str, Any]:
    if isinstance(message, Pose):
        return pose_fields(message)
    if isinstance(message, LaserScan):
        return scan_fields(message)
    fields: dict[str, Any] = msgspec.to_builtins(message)  # feedback and status: as they are
    if isinstance(message, NavigateToFeedback):
        fields["received"] = now
    return fields


__all__ = ["Hub"]
