"""``turtlectl record``: what arrives on key expressions, written to a recording (cli.recording.bag).

Nothing here prints; ``record`` yields progress for the command to show.  Samples are taken
with their receive time on Zenoh's threads and written on the caller's thread (which first
learns a type turtlectl was not built with from the nodes that use it: runtime.client.typebook), which also
closes a chunk before its first message is a second old (cli.recording.bag.CHUNK_SPAN); when ``stop`` is set (Ctrl-C, SIGTERM) or the duration is over,
what is queued is written and the file is finished.  A lost router is waited for as every
long-running tool does (cli.tools.routerwatch: a line when it is lost and one when it is back,
yielded as text), and the time without it is marked in the file (``BagWriter.mark_gap``).
"""

from __future__ import annotations

import dataclasses
import datetime
import queue
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import msgspec
import zenoh

from turtlectl.cli.recording.bag import BagWriter
from turtlectl.cli.tools.routerwatch import watch
from turtlectl.messages.codec import MEDIA_TYPE, TYPES_BY_NAME
from turtlectl.messages.described import describable
from turtlectl.messages.keys import WORLD_KEY
from turtlectl.messages.world import World
from turtlectl.runtime.client import presence
from turtlectl.runtime.client.services import RouterLost
from turtlectl.runtime.client.session import check_key, client_session
from turtlectl.runtime.client.typebook import TypeBook

ALL = "**"  # every key (not turtlectl's liveliness tokens: keys under @ are not matched by **)
PROGRESS_PERIOD = 0.5  # s between two progress reports


@dataclasses.dataclass(frozen=True)
class Progress:
    path: Path
    elapsed: float  # s since recording began
    messages: int
    size: int  # bytes written so far
    done: bool = False


def default_path(now: datetime.datetime | None = None, profile: str = "") -> Path:
    """``turtlectl_<date>-<time>.mcap`` in the current folder, as rosbag2 names its bags (a ROS 2
    bag, ``profile`` "ros2": the folder ``turtlectl_<date>-<time>``)."""
    now = now or datetime.datetime.now()
    return Path(f"turtlectl_{now:%Y_%m_%d-%H_%M_%S}" + ("" if profile == "ros2" else ".mcap"))


def keys_to_record(topics: list[str], everything: bool, exclude: list[str]) -> tuple[list[str], list[str]]:
    """The key expressions to subscribe to and those to leave out, checked (BadInput)."""
    from turtlectl.runtime.client.errors import BadInput

    if everything and topics:
        raise BadInput("give topics or -a/--all, not both")
    if not everything and not topics:
        raise BadInput("nothing to record: give topics (key expressions) or -a/--all for every topic")
    keys = [ALL] if everything else list(dict.fromkeys(check_key(t) for t in topics))
    return keys, [check_key(e) for e in exclude]


def learn(book: TypeBook, encoding: str) -> None:
    """Before a sample of ``encoding`` is written: the type it names, if turtlectl was not built
    with it (a user's own), learnt from the nodes that use it, so that it is recorded with its
    JSON Schema as a built-in is; a type no node describes stays unknown (the sample is kept raw).
    On the writer's thread: the query blocks, which a Zenoh callback must not."""
    media, _, name = encoding.partition(";")
    if media == MEDIA_TYPE and describable(name) and name not in TYPES_BY_NAME:
        book.resolve(name)


class _Drawing:
    """The scene for ``record --scene``: drawn from each message, the world once a second."""

    def __init__(self, writer: BagWriter, world: World):
        from turtlectl.cli.foxglove.scene import SceneMaker  # foxglove: only when asked for

        self.writer = writer
        self.maker = SceneMaker(world)
        self._next_world = 0

    def draw(self, key: str, message: object, when: int) -> None:
        for topic, drawn in self.maker.on_message(key, message, when):
            self.writer.add_scene(topic, drawn, when)

    def tick(self) -> None:
        now = time.time_ns()
        if now >= self._next_world:
            self._next_world = now + 1_000_000_000
            topic, drawn = self.maker.world_update(now)
            self.writer.add_scene(topic, drawn, now)


def open_writer(path: Path, library: str, profile: str = "") -> BagWriter:
    """The writer of a recording in ``profile``: "" turtlectl's own (cli.recording.bag), "ros2" a
    ROS 2 bag (cli.recording.ros2bag, which needs the ros2 extra)."""
    if profile == "ros2":
        from turtlectl.cli.recording.ros2bag import Ros2BagWriter

        return Ros2BagWriter(path, library)  # type: ignore[return-value]  # the same methods
    return BagWriter(path, library)


def _notes(writer: object) -> Iterator[str]:
    """The lines a writer has to say (a ROS 2 bag's topics left out), each once."""
    notes = getattr(writer, "notes", None)
    while notes:
        yield notes.pop(0)


def record(
    connect: str,
    domain: str,
    keys: list[str],
    exclude: list[str],
    path: Path,
    duration: float | None,
    stop: threading.Event,
    library: str = "turtlectl",
    scene: bool = False,
    exit_on_loss: bool = False,
    profile: str = "",
) -> Iterator[Progress | str]:
    """Record ``keys`` (minus ``exclude``) into ``path`` until ``stop`` is set or ``duration`` s
    have passed; yields a Progress about twice a second and a last one once the file is closed,
    and a line (str) when the router is lost and when it is back (with ``exit_on_loss``,
    RouterLost once the file is finished, the gap marked).
    With ``scene``, the Foxglove scene drawn from the messages is recorded too (cli.foxglove.scene).
    ``profile`` "ros2": a ROS 2 bag (cli.recording.ros2bag), each topic it leaves out said once (a line)."""
    exprs = [zenoh.KeyExpr(k) for k in keys]
    excluded = [zenoh.KeyExpr(k) for k in exclude]
    inbox: queue.SimpleQueue[tuple[str, str, bytes, int]] = queue.SimpleQueue()

    def taker(index: int):
        earlier = exprs[:index]

        def on_sample(sample: zenoh.Sample) -> None:  # Zenoh thread: stamp and queue only
            received = time.time_ns()
            key = sample.key_expr
            # a key matched by two of the expressions reaches two subscribers: kept once
            if any(e.intersects(key) for e in earlier) or any(e.intersects(key) for e in excluded):
                return
            inbox.put((str(key), str(sample.encoding), sample.payload.to_bytes(), received))

        return on_sample

    with client_session(connect, domain) as session:
        writer = open_writer(path, library, profile)
        try:
            world = World()
            for reply in session.get(WORLD_KEY, timeout=1.0):  # the world, for a replay to draw
                if reply.ok is not None:
                    writer.attach_world(reply.ok.payload.to_bytes(), time.time_ns())
                    world = msgspec.json.decode(reply.ok.payload.to_bytes(), type=World)
                    break
            drawing = _Drawing(writer, world) if scene else None
            book = TypeBook(session)  # a type turtlectl was not built with, learnt from its nodes
            subs = [presence.subscriber(session, k, taker(i)) for i, k in enumerate(keys)]
            started = time.monotonic()
            next_report = started
            router = watch(session, connect, f"messages on {', '.join(keys)}", exit_on_loss)
            lost_at = 0  # ns since the epoch the router was lost, 0 while it is there
            try:
                while not stop.is_set() and (duration is None or time.monotonic() - started < duration):
                    try:
                        sample = inbox.get(timeout=0.05)
                        learn(book, sample[1])
                        message = writer.add(*sample)
                        yield from _notes(writer)
                        if drawing is not None and message is not None:
                            drawing.draw(sample[0], message, sample[3])
                    except queue.Empty:
                        pass
                    now = time.monotonic()
                    try:
                        line = router.check(now)
                    except RouterLost:  # --exit-on-loss: the file says where it ends, and why
                        writer.mark_gap(time.time_ns())
                        raise
                    if line is not None:
                        if router.lost:
                            lost_at = time.time_ns()
                        else:
                            writer.mark_gap(lost_at, time.time_ns())
                            lost_at = 0
                        yield line
                    if drawing is not None:
                        drawing.tick()
                    writer.tick()  # a chunk whose first message is old enough is closed
                    if now >= next_report:
                        next_report = now + PROGRESS_PERIOD
                        yield Progress(path, now - started, writer.messages, writer.size)
            finally:
                if lost_at:
                    writer.mark_gap(lost_at)  # still lost at the end
                for sub in subs:
                    sub.undeclare()
                while True:  # what was received before the end is kept
                    try:
                        sample = inbox.get_nowait()
                    except queue.Empty:
                        break
                    learn(book, sample[1])
                    writer.add(*sample)
            elapsed = time.monotonic() - started
        finally:
            writer.close()
    size = sum(p.stat().st_size for p in path.iterdir()) if path.is_dir() else path.stat().st_size
    yield Progress(path, elapsed, writer.messages, size, done=True)
