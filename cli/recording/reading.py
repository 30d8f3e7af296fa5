"""Reading recordings (``play``, ``info``, ``recover``): a file written by cli.recording.bag,
in log-time order, with what it holds; one that was never closed is read as far as it is
whole (what a recording holds, and why it may not be closed: cli.recording.bag).  A type
turtlectl was not built with (a user's own) is known from the JSON Schema the file holds for it
(messages.jsonform.message_class), so ``info`` names it and ``play`` sends it as it was sent.
A recording made before types were named by package names turtlectl's own types bare (``Pose``):
they are read as ``turtlectl/Pose`` (``full_name``, the one place); a user's type recorded under a
bare name keeps it.  No Zenoh here."""

from __future__ import annotations

import dataclasses
import struct
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from turtlectl.cli.recording.bag import GAP, JSON, JSON_SCHEMA, PROTOBUF, WORLD, Record, RecordingError
from turtlectl.messages.codec import TYPES_BY_NAME
from turtlectl.messages.naming import BUILTIN_PACKAGE


@dataclasses.dataclass(frozen=True)
class TopicInfo:
    key: str
    type_name: str  # "" for raw payloads
    encoding: str  # the MCAP message encoding
    count: int
    rate: float  # mean messages per second over the recording (0 if it spans no time)


@dataclasses.dataclass(frozen=True)
class Gap:
    """A time the recorder had no router: nothing was recorded from ``lost`` to ``back``."""

    lost: int  # ns since the epoch
    back: int  # ns since the epoch; 0: still lost when the recording ended
    duration: float  # s (to the end of the recording when it never came back)


@dataclasses.dataclass(frozen=True)
class Info:
    path: str
    size: int
    closed: bool  # False: no summary section (the recorder was killed); what is complete was read
    start: int  # ns since the epoch (0 when empty)
    end: int
    count: int
    topics: list[TopicInfo]
    gaps: list[Gap] = dataclasses.field(default_factory=list)  # the times without router, in order

    @property
    def duration(self) -> float:
        """Seconds from the first message to the last."""
        return (self.end - self.start) / 1e9


_DAMAGE: tuple[type[BaseException], ...] = (
    struct.error,
    ValueError,
    EOFError,
    OSError,
)  # OSError: a seek before the start


class Recording:
    """A recording opened for reading: ``records()`` in log-time order, ``info()``.
    Raises RecordingError if ``path`` is not an MCAP file or is unreadable."""

    def __init__(self, path: Path):
        from mcap.reader import make_reader

        self.path = path
        self.file = mcap_file(path)  # a ROS 2 bag is a folder: its MCAP file
        self._damage = read_errors()
        self._ros2: Any = None  # the reader of CDR messages (cli.recording.ros2bag), made when first needed
        try:
            with open(self.file, "rb") as f:
                magic = f.read(8)
        except FileNotFoundError:
            raise RecordingError(f"{path}: no such file") from None
        except OSError as exc:
            raise RecordingError(f"cannot read {path}: {exc.strerror or exc}") from None
        if magic != b"\x89MCAP0\r\n":
            raise RecordingError(f"{path} is not an MCAP file (a recording made by `turtlectl record`)")
        self.summary: Any = None
        try:
            with open(self.file, "rb") as f:
                self.summary = make_reader(f).get_summary()
        except self._damage:
            self.summary = None
        self.closed = self.summary is not None
        if not self.closed:
            self._check_header()
        self._check_schemas()

    def _check_header(self) -> None:
        from mcap.records import Header
        from mcap.stream_reader import StreamReader

        try:
            with open(self.file, "rb") as f:
                first = next(iter(StreamReader(f).records), None)
        except self._damage:
            first = None
        if not isinstance(first, Header):
            raise RecordingError(f"{self.path} is truncated: not even its header can be read")

    def _check_schemas(self) -> None:
        for schema, channel in self._channels():
            if channel.message_encoding == PROTOBUF and schema is not None and schema.name.startswith("foxglove."):
                continue  # the scene of record --scene
            unknown = schema is None or (full_name(schema.name) not in TYPES_BY_NAME and not _learn(schema))
            if channel.message_encoding == PROTOBUF or (channel.message_encoding == JSON and unknown):
                name = schema.name if schema is not None else "no schema"
                known = ", ".join(sorted(TYPES_BY_NAME))
                raise RecordingError(
                    f"{self.path}: channel {channel.topic} has an unknown type ({name}); turtlectl knows {known}"
                )

    def _channels(self) -> Iterator[tuple[Any, Any]]:
        """(schema or None, channel) of every channel: from the summary, or from a scan."""
        if self.summary is not None:
            for channel in self.summary.channels.values():
                yield self.summary.schemas.get(channel.schema_id), channel
            return
        seen: set[int] = set()
        for schema, channel, _ in self._scan():
            if channel.id not in seen:
                seen.add(channel.id)
                yield schema, channel

    def _scan(self) -> Iterator[tuple[Any, Any, Any]]:
        """Every complete message of a file that was not closed, in file order; stops at the damage."""
        from mcap.reader import NonSeekingReader

        with open(self.file, "rb") as f:
            try:
                yield from NonSeekingReader(f, validate_crcs=True).iter_messages(log_time_order=False)
            except self._damage:
                return

    def records(self, keys: list[str] | None = None) -> Iterator[Record]:
        """Every message (of channels ``keys`` only, if given) in log-time order."""
        if self.summary is not None:
            from mcap.reader import make_reader

            topics = None if keys is None else [*keys, *(f"/{k}" for k in keys if not k.startswith("/"))]
            with open(self.file, "rb") as f:
                try:
                    for schema, channel, message in make_reader(f).iter_messages(topics=topics, log_time_order=True):
                        record = self._record(schema, channel, message)
                        if record is not None:
                            yield record
                except self._damage as exc:
                    raise RecordingError(f"{self.path} is damaged: {exc}") from None
            return
        # no index: the file's order, which is the order received (each log time is its arrival)
        for schema, channel, message in self._scan():
            if keys is None or channel.topic in keys or _plain(channel.topic) in keys:
                record = self._record(schema, channel, message)
                if record is not None:
                    yield record

    def _record(self, schema: Any, channel: Any, message: Any) -> Record | None:
        """One message as a Record; a ROS 2 bag's CDR message as the turtlectl message its type maps
        to (cli.recording.ros2bag), on the key of its topic; one of a ROS type that maps to none as it
        is (its CDR bytes, played as they are: a ROS-aware subscriber can read them)."""
        from turtlectl.nodes.ros2_fields import readable

        if not _is_ros2(schema, channel) or not readable(schema.name):
            return _record(schema, channel, message)
        if self._ros2 is None:
            from turtlectl.cli.recording.ros2bag import Ros2Decoder

            self._ros2 = Ros2Decoder()
        decoded = self._ros2.message(channel.topic, schema.name, schema.data.decode(errors="replace"), message.data)
        if decoded is None:
            return None
        from turtlectl.messages import encoding_for
        from turtlectl.messages.codec import type_name
        from turtlectl.messages.jsonform import to_json

        stamp = getattr(decoded, "stamp", 0)
        if not stamp and "stamp" in type(decoded).__struct_fields__:  # no header: stamped when recorded
            import msgspec

            decoded, stamp = msgspec.structs.replace(decoded, stamp=message.log_time), message.log_time
        return Record(
            key=_plain(channel.topic),
            type_name=type_name(type(decoded)),
            encoding=encoding_for(type(decoded)),
            log_time=message.log_time,
            publish_time=stamp or message.publish_time,
            sequence=message.sequence,
            data=to_json(decoded),
        )

    def ros_fields(self, record: Record) -> dict | None:
        """A ROS 2 bag's message of a ROS type that maps to no turtlectl type (a raw ``record`` of a
        ``cdr`` channel) as nested dicts of its fields, for ``plot``; None if it is none or does not decode."""
        schema = next((sc for sc, ch in self._channels() if ch.topic == record.key and _is_ros2(sc, ch)), None)
        if schema is None:
            return None
        if self._ros2 is None:
            from turtlectl.cli.recording.ros2bag import Ros2Decoder

            self._ros2 = Ros2Decoder()
        return self._ros2.fields(schema.name, schema.data.decode(errors="replace"), record.data)

    def unmapped(self) -> dict[str, str]:
        """A ROS 2 bag's topics whose ROS type maps to no turtlectl type (topic -> ROS type): ``play``
        publishes their CDR bytes as they are, ``plot`` reads them by their own fields (``ros_fields``)."""
        from turtlectl.nodes.ros2_fields import readable

        return {
            channel.topic: schema.name
            for schema, channel in self._channels()
            if _is_ros2(schema, channel) and not readable(schema.name)
        }

    def world(self) -> bytes | None:
        """The world attached to the recording (JSON), or None."""
        from mcap.records import Attachment
        from mcap.stream_reader import StreamReader

        with open(self.file, "rb") as f:
            try:
                for record in StreamReader(f, emit_chunks=True).records:  # chunks skipped whole
                    if isinstance(record, Attachment) and record.name == WORLD:
                        return bytes(record.data)
            except self._damage:
                pass
        return None

    def gaps(self, end: int = 0) -> list[Gap]:
        """The times the recorder had no router (bag.GAP metadata), in order; a gap never closed
        lasts until ``end`` (ns since the epoch, the last message)."""
        from mcap.records import Metadata
        from mcap.stream_reader import StreamReader

        found: list[Gap] = []
        with open(self.file, "rb") as f:
            try:
                for record in StreamReader(f, emit_chunks=True).records:  # chunks skipped whole
                    if isinstance(record, Metadata) and record.name == GAP:
                        try:
                            lost, back = int(record.metadata["lost"]), int(record.metadata.get("back") or 0)
                        except (KeyError, ValueError):
                            continue  # not one turtlectl wrote
                        found.append(Gap(lost, back, max(0, (back or max(end, lost)) - lost) / 1e9))
            except self._damage:
                pass
        return sorted(found, key=lambda g: g.lost)

    def info(self) -> Info:
        counts: dict[int, int] = {}
        channels: dict[int, tuple[Any, Any]] = {}
        start = end = 0
        if self.summary is not None and self.summary.statistics is not None:
            stats = self.summary.statistics
            counts = dict(stats.channel_message_counts)
            channels = {c.id: (self.summary.schemas.get(c.schema_id), c) for c in self.summary.channels.values()}
            start, end = (stats.message_start_time, stats.message_end_time) if stats.message_count else (0, 0)
        else:
            for schema, channel, message in self._scan():
                channels.setdefault(channel.id, (schema, channel))
                counts[channel.id] = counts.get(channel.id, 0) + 1
                start = message.log_time if not start else min(start, message.log_time)
                end = max(end, message.log_time)
        span = (end - start) / 1e9
        topics = [
            TopicInfo(
                key=channel.topic,
                type_name=full_name(schema.name) if schema is not None else "",
                encoding=channel.message_encoding,
                count=counts.get(cid, 0),
                rate=counts.get(cid, 0) / span if span > 0 else 0.0,
            )
            for cid, (schema, channel) in sorted(channels.items(), key=lambda item: item[1][1].topic)
        ]
        return Info(
            path=str(self.path),
            size=self.file.stat().st_size,
            closed=self.closed,
            start=start,
            end=end,
            count=sum(counts.values()),
            topics=topics,
            gaps=self.gaps(end),
        )


CDR = "cdr"  # a ROS 2 bag's message encoding
ROS2MSG = "ros2msg"  # a ROS 2 bag's schema encoding (the .msg text)


def _is_ros2(schema: Any, channel: Any) -> bool:
    return schema is not None and channel.message_encoding == CDR and schema.encoding == ROS2MSG


def _plain(topic: str) -> str:
    """A ROS topic as a key: the leading '/' dropped."""
    return topic[1:] if topic.startswith("/") and len(topic) > 1 else topic


def mcap_file(path: Path) -> Path:
    """The MCAP file of a recording: ``path`` itself, or in a ROS 2 bag's folder its one ``.mcap`` file.
    RecordingError (exit 2) for a folder holding none, or several (a split bag)."""
    if not path.is_dir():
        return path
    found = sorted(path.glob("*.mcap"))
    if len(found) == 1:
        return found[0]
    if not found:
        other = " (its storage is sqlite3: turtlectl reads MCAP bags only)" if any(path.glob("*.db3")) else ""
        raise RecordingError(f"{path} is a folder without an MCAP file{other}")
    raise RecordingError(f"{path} holds {len(found)} MCAP files (a split bag): give one of them")


def _learn(schema: Any) -> bool:
    """A type turtlectl was not built with (a user's own, recorded with its JSON Schema) known
    from the schema the file holds, as a tool knows it from a node's description; False if the
    schema is not one turtlectl writes."""
    import json

    from turtlectl.messages.codec import register
    from turtlectl.messages.jsonform import message_class

    if schema.encoding != JSON_SCHEMA:
        return False
    try:
        register(message_class(schema.name, json.loads(schema.data)))
    except ValueError:  # not JSON, or not a message's schema (DescriptionError), or a name taken
        return False
    return True


def full_name(name: str) -> str:
    """A recorded schema's type name as turtlectl names it: a built-in's bare name from a
    recording made before types were named by package (``Pose``) is ``turtlectl/Pose``; any other
    as it is."""
    builtin = f"{BUILTIN_PACKAGE}/{name}"
    return builtin if "/" not in name and builtin in TYPES_BY_NAME else name


def _retagged(data: bytes, name: str) -> bytes:
    """A legacy built-in's recorded JSON with its ``type`` member the full name (as is if it is no JSON object)."""
    import json

    try:
        value = json.loads(data)
    except ValueError:
        return data
    if not isinstance(value, dict) or "type" not in value:
        return data
    return json.dumps({**value, "type": name}, separators=(",", ":")).encode()


def _record(schema: Any, channel: Any, message: Any) -> Record:
    typed = schema is not None and channel.message_encoding == JSON
    name = full_name(schema.name) if typed else ""
    encoding = channel.metadata.get("zenoh_encoding", channel.message_encoding)
    data = message.data
    if typed and name != schema.name:  # a legacy built-in: its tag and encoding as they are now
        data, encoding = _retagged(data, name), encoding.replace(f";{schema.name}", f";{name}")
    return Record(
        key=channel.topic,
        type_name=name,
        encoding=encoding,
        log_time=message.log_time,
        publish_time=message.publish_time,
        sequence=message.sequence,
        data=data,
        scene=channel.message_encoding == PROTOBUF,
    )


def read_errors() -> tuple[type[BaseException], ...]:
    """What reading a damaged or cut MCAP file raises (mcap's own errors, zstd's, a short read)."""
    from mcap.exceptions import McapError

    try:
        from zstandard import ZstdError
    except ImportError:
        return (*_DAMAGE, McapError)
    return (*_DAMAGE, McapError, ZstdError)
