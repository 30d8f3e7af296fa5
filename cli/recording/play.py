"""``turtlectl play``: a recording published again, each message at its recorded offset.

Nothing here prints.  ``plan`` (pure) picks and remaps what is played; ``play`` publishes it
on an absolute schedule: message i is due at ``start + (log_time_i - first) / rate`` on the
monotonic clock (time spent paused moves the start), so delays never add up; messages get a
fresh ``stamp`` unless ``keep_stamps``.  With ``clock_hz`` it also publishes ``clock`` (as
``ros2 bag play --clock``): the recording's time at the point played, that many times a wall
second, so nodes started with ``use_sim_time`` run on the recording's time (at ``rate``); the
messages are then stamped with the time they were recorded at, which that clock shows.  It yields each message's lateness (actual − scheduled)
for the progress line and the benchmark.  While it plays, it describes each user type it
publishes on ``turtlectl/types/<TypeName>/play``, as a node does, so the tools understand it
with no node of that type running.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator

import msgspec
import zenoh

from turtlectl.cli.recording.bag import Record
from turtlectl.cli.recording.reading import Recording
from turtlectl.messages import ALL_TYPES, Clock, Log, Message, encode, encoding_for
from turtlectl.messages.codec import TYPES_BY_NAME, type_name
from turtlectl.messages.described import describable, describe
from turtlectl.messages.keys import CLOCK, WORLD_KEY, type_key
from turtlectl.runtime.client.errors import BadInput
from turtlectl.runtime.client.session import check_key, client_session, require

SPIN = 0.0015  # s before a message is due when sleeping stops and the wait spins (timer slack)
DESCRIBER = "play"  # the 'node' in turtlectl/types/<TypeName>/play


@dataclasses.dataclass(frozen=True)
class Played:
    key: str
    offset: float  # s from the first message played, in the recording's time
    late: float  # s: when it went out minus when it was due (wall, after dividing by the rate)
    index: int
    total: int
    loop: int
    paused: bool = False  # yielded once as a pause begins (the message is not sent yet)


def parse_remaps(remaps: list[str]) -> dict[str, str]:
    """``OLD:=NEW`` pairs (as ROS's remapping) as a dict; BadInput if malformed."""
    out: dict[str, str] = {}
    for text in remaps:
        old, sep, new = text.partition(":=")
        if not sep or not old or not new:
            raise BadInput(f"--remap {text!r}: write it as OLD:=NEW, e.g. robot/status:=replay/status")
        out[check_key(old, publish=True)] = check_key(new, publish=True)
    return out


def _plain(topic: str) -> str:
    """A recorded channel's topic as a key: a ROS-style leading '/' dropped."""
    return topic[1:] if topic.startswith("/") and len(topic) > 1 else topic


def plan(records: Iterable[Record], start_offset: float) -> list[Record]:
    """The records to play, those from ``start_offset`` s after the first one on."""
    chosen = [r for r in records if not r.scene]  # the scene is drawn from the rest
    if not chosen:
        return chosen
    first = chosen[0].log_time
    return [r for r in chosen if (r.log_time - first) / 1e9 >= start_offset]


def _payload(record: Record, message: Message | None, keep_stamps: bool, recorded: bool = False) -> tuple[bytes, str]:
    """What to publish for ``record`` (whose ``message()`` is ``message``): msgpack of the
    message (freshly stamped unless ``keep_stamps``; with ``recorded``, stamped with the time it
    was recorded at, as a played clock shows it), or its raw bytes; and their encoding.  A log
    record (Log) always keeps its stamp: when it was logged is what it says, as ``ros2 bag play``
    leaves ``/rosout`` alone."""
    if message is None:
        return record.data, record.encoding
    if not keep_stamps and "stamp" in type(message).__struct_fields__ and not isinstance(message, Log):
        message = msgspec.structs.replace(message, stamp=record.log_time if recorded else time.time_ns())
    return encode(message), encoding_for(type(message))


def user_types(records: Iterable[Record]) -> list[type[Message]]:
    """The message classes of ``records`` that are not built-ins (a user's own types, known
    from the file's schemas), each once, by name."""
    builtin = set(ALL_TYPES)
    found: dict[str, type[Message]] = {}
    for r in records:
        if r.type_name and not r.scene and r.type_name not in found and describable(r.type_name):
            cls = TYPES_BY_NAME.get(r.type_name)
            if cls is not None and cls not in builtin:
                found[r.type_name] = cls
    return [found[name] for name in sorted(found)]


def serve_types(session: zenoh.Session, classes: list[type[Message]]) -> list[zenoh.Queryable]:
    """Describe each of ``classes`` on ``turtlectl/types/<TypeName>/play`` (JSON
    TypeDescription), as a node describes the types it uses; undeclare them when play ends."""
    queryables = []
    for cls in classes:
        key = type_key(type_name(cls), DESCRIBER)
        document = msgspec.json.encode(describe(cls))

        def on_query(query: zenoh.Query, key: str = key, document: bytes = document) -> None:
            query.reply(key, document, encoding=zenoh.Encoding.APPLICATION_JSON)

        queryables.append(session.declare_queryable(key, on_query))
    return queryables


def serve_world(session: zenoh.Session, document: bytes | None) -> zenoh.Queryable | None:
    """Answer ``turtlectl/world`` with the recorded world while playing, unless a simulator
    answers it already (``turtlectl view`` draws it; the queryable ends with the session)."""
    if document is None or any(r.ok is not None for r in session.get(WORLD_KEY, timeout=0.5)):
        return None

    def on_query(query: zenoh.Query) -> None:
        query.reply(WORLD_KEY, document, encoding=zenoh.Encoding.APPLICATION_JSON)

    return session.declare_queryable(WORLD_KEY, on_query)


def play(
    connect: str,
    domain: str,
    recording: Recording,
    rate: float,
    start_offset: float,
    keys: list[str] | None,
    remap: dict[str, str],
    keep_stamps: bool,
    loop: bool,
    paused: Callable[[], bool],
    stopped: Callable[[], bool],
    clock_hz: float | None = None,
) -> Iterator[Played]:
    """Publish the recording (``keys`` only if given, renamed by ``remap``) at ``rate`` times its
    speed, from ``start_offset`` s; again and again with ``loop``.  ``paused()`` holds the
    schedule; ``stopped()`` ends it.  ``clock_hz``: also publish the recording's time on ``clock``
    that many times a second (the module's docstring)."""
    if rate <= 0:
        raise BadInput("--rate must be above 0")
    # channels are keys as recorded; a ROS 2 bag's start with '/', dropped as everywhere in turtlectl
    wanted = None if keys is None else set(keys)
    selected = [r for r in recording.records() if wanted is None or _plain(r.key) in wanted]
    if clock_hz:  # the clock played is the recording's time: a recorded one would be a second clock
        selected = [r for r in selected if _plain(r.key) != CLOCK]
    records = plan(selected, start_offset)
    if not records and start_offset > 0.0 and plan(selected, 0.0):
        length = recording.info().duration
        raise BadInput(f"--start-offset {start_offset:g} s is past the end of {recording.path} ({length:.3g} s long)")
    if not records:
        raise BadInput(f"nothing to play in {recording.path}" + (f" on {', '.join(keys)}" if keys else ""))
    targets = {}  # recorded channel -> the key it is played on
    for topic in {r.key for r in records}:
        try:
            targets[topic] = check_key(remap.get(_plain(topic), _plain(topic)), publish=True)
        except BadInput as exc:
            raise BadInput(f"{recording.path}: channel {topic!r} cannot be played: {exc.message}") from None
    first = records[0].log_time
    with client_session(connect, domain) as session:
        world = serve_world(session, recording.world())  # kept: a queryable lives while referenced
        described = serve_types(session, user_types(records))
        publishers: dict[tuple[str, str], zenoh.Publisher] = {}
        clock = Clocked(session, first, rate, clock_hz) if clock_hz else None
        round_ = 0
        try:
            while True:
                start = time.monotonic()
                for index, record in enumerate(records):
                    offset = (record.log_time - first) / 1e9
                    message = record.message()  # decoded before it is due: only stamping is left then
                    while True:
                        if stopped():
                            return
                        if clock is not None:
                            clock.tick(start)
                        if paused():
                            yield Played(record.key, offset, 0.0, index, len(records), round_, paused=True)
                            held = time.monotonic()
                            while paused() and not stopped():
                                time.sleep(0.02)  # pacing: paused by the user
                            start += time.monotonic() - held
                            continue
                        due = start + offset / rate
                        wait = due - time.monotonic()
                        if wait <= 0:
                            break
                        if wait > SPIN:
                            nap = min(wait - SPIN, 0.05, clock.wait() if clock is not None else 0.05)
                            time.sleep(max(nap, 0.0))  # pacing: the schedule (short, to see pause/stop)
                    payload, encoding = _payload(record, message, keep_stamps, recorded=clock is not None)
                    key = targets[record.key]
                    pub = publishers.get((key, encoding))
                    if pub is None:
                        require(session, "publish", key)  # a --secure router would drop it without a word
                        pub = session.declare_publisher(key, encoding=zenoh.Encoding(encoding))
                        publishers[(key, encoding)] = pub
                    pub.put(payload)
                    late = time.monotonic() - due
                    yield Played(record.key, offset, late, index, len(records), round_)
                if not loop:
                    return
                round_ += 1
        finally:
            if clock is not None:
                clock.pub.undeclare()
            for pub in publishers.values():
                pub.undeclare()
            if world is not None:
                world.undeclare()
            for queryable in described:
                queryable.undeclare()


class Clocked:
    """``play --clock``: the recording's time on ``clock``, ``hz`` times a wall second."""

    def __init__(self, session: zenoh.Session, first: int, rate: float, hz: float):
        require(session, "publish", CLOCK)
        self.pub = session.declare_publisher(CLOCK, encoding=zenoh.Encoding(encoding_for(Clock)))
        self.first, self.rate, self.period = first, rate, 1.0 / hz
        self.next = 0.0  # monotonic s: when the next one is due
        self.seq = 0

    def tick(self, start: float) -> None:
        """Publish the time played now (``start``: when the recording's first message was due),
        if one is due."""
        now = time.monotonic()
        if now >= self.next:
            played = self.first + round(max(0.0, now - start) * self.rate * 1e9)
            self.pub.put(encode(Clock(clock=played, real_time_factor=self.rate, stamp=played, seq=self.seq)))
            self.next, self.seq = now + self.period, self.seq + 1

    def wait(self) -> float:
        """s until the next one is due."""
        return self.next - time.monotonic()


@contextlib.contextmanager
def space_toggles(active: bool) -> Iterator[Callable[[], bool]]:
    """On a terminal (``active``): the space key toggles pause while the block runs, the
    terminal restored after; yields ``paused()``.  Otherwise ``paused()`` is always False."""
    state = threading.Event()
    if not active:
        yield state.is_set
        return
    import termios
    import tty

    fd = sys.stdin.fileno()
    saved = termios.tcgetattr(fd)
    done = threading.Event()

    def read_keys() -> None:
        import select

        while not done.is_set():
            ready, _, _ = select.select([fd], [], [], 0.1)
            if ready:
                key = os.read(fd, 1)
                if key == b" ":
                    if state.is_set():
                        state.clear()
                    else:
                        state.set()
                elif not key:
                    return

    tty.setcbreak(fd)
    reader = threading.Thread(target=read_keys, name="keys", daemon=True)
    reader.start()
    try:
        yield state.is_set
    finally:
        done.set()
        reader.join(0.5)
        termios.tcsetattr(fd, termios.TCSADRAIN, saved)
