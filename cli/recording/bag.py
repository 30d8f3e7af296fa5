"""Recordings (``record``, ``play``, ``info``): MCAP files of turtlectl messages.  No Zenoh here.

What a recording holds.  An MCAP file, chunked with zstd.  Each key recorded is a channel
whose topic is the key; each message type a schema named by its wire name ("Pose"), a JSON
Schema (``messages.jsonform.json_schema``; a user's own type too, once ``record`` has learnt it
from its nodes, and ``reading`` knows it again from that schema), and messages are JSON (``messages.jsonform``,
lossless: ``inf`` and ``NaN`` survive), so Foxglove opens the file as it is.  Per message:
``log_time`` is when the recorder received it, ``publish_time`` its own ``stamp`` (its log
time if it has none), ``sequence`` its ``seq``.  A payload that is not a known message (a
raw publisher, garbage) is kept as it came: a channel without schema whose message encoding
is the sample's Zenoh encoding, the bytes unchanged.  The world the run happened in (the
simulator's ``turtlectl/world`` answer) is attached as ``turtlectl/world`` (JSON), so that a
replay can draw it.  A time the recorder had no router (it was lost, then back; or lost until
the end) is an MCAP metadata record named ``turtlectl/gap`` whose ``lost`` and ``back`` are ns
since the epoch as decimal strings (``back`` empty: still lost when the recording ended), as
the recorder noticed them (within ``runtime.client.session.ROUTER_CHECK`` s); ``info`` lists them and
``play`` reads past them (they hold no message).  With ``record --scene`` the file also holds the Foxglove scene
(cli.foxglove.scene: channels ``scene``, ``scene/scan`` and ``log``, Foxglove's well-known protobuf schemas),
which ``play`` leaves out (it is drawn from the other messages).

Crash safety.  A chunk is closed (and on disk) once its first message is ``CHUNK_SPAN`` old, by
the messages' own receive times (``add``) and by the clock (``tick``), so a recorder killed with
SIGKILL loses at most the last second; a file that was never closed has no summary section:
reading it reads every complete chunk and says it was not closed, and ``turtlectl recover``
(cli.recording.recover) writes it whole and indexed.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import IO, Any

from turtlectl.messages import DecodeError, Message, decode, encoding_for, type_from_encoding
from turtlectl.messages.codec import TYPES_BY_NAME, type_name
from turtlectl.messages.jsonform import JsonFormError, from_json, json_schema, to_json
from turtlectl.runtime.client.errors import BadInput

PROFILE = ""  # no MCAP profile: our own JSON messages (ros1/ros2 profiles mean their encodings)
JSON = "json"  # MCAP's well-known message encoding
JSON_SCHEMA = "jsonschema"  # MCAP's well-known schema encoding
PROTOBUF = "protobuf"  # the scene's encoding (Foxglove's well-known schemas)
WORLD = "turtlectl/world"  # the attachment holding the world the run happened in (JSON)
GAP = "turtlectl/gap"  # a metadata record: a time without router (``lost``, ``back``: ns since the epoch)
CHUNK_SPAN = 800_000_000  # ns: a chunk is closed once its first message is this old (< 1 s lost)
CHUNK_SIZE = 1 << 20  # bytes (uncompressed) a chunk may reach before it is closed anyway


class RecordingError(BadInput):
    """A file that is not a recording turtlectl can read (exit 2)."""


@dataclasses.dataclass(frozen=True)
class Record:
    """One recorded message.  ``type_name`` is "" for a payload kept raw (no known type);
    ``encoding`` is the Zenoh encoding it travelled with; ``data`` is what the file holds
    (JSON for a typed message, the raw bytes otherwise)."""

    key: str
    type_name: str
    encoding: str
    log_time: int  # ns since the epoch: received by the recorder
    publish_time: int  # ns since the epoch: the message's own stamp
    sequence: int
    data: bytes
    scene: bool = False  # a drawing for Foxglove (record --scene), not a message of the system

    def message(self) -> Message | None:
        """The message, or None for a raw payload.  Raises RecordingError if the JSON is bad."""
        if not self.type_name or self.scene:
            return None
        try:
            return from_json(self.data, TYPES_BY_NAME[self.type_name])
        except JsonFormError as exc:
            raise RecordingError(f"a message on {self.key} cannot be read: {exc}") from None


# -- writing ---------------------------------------------------------------------------------


def refuse_existing(path: Path) -> None:
    """A recording is never written over an existing file: say so (exit 2) before anything starts."""
    if path.exists():
        raise BadInput(f"{path} already exists: choose another name with -o")


class BagWriter:
    """Writes a recording at ``path`` (which must not exist yet): ``add`` each sample as it was
    received, ``tick`` often (it closes the chunk once a second), ``close`` at the end."""

    def __init__(self, path: Path, library: str = "turtlectl"):
        from mcap.writer import CompressionType, Writer  # here: only record imports mcap's writer

        self.path = path
        try:
            self._file: IO[bytes] = open(path, "xb")  # noqa: SIM115 - closed by close()
        except FileExistsError:
            refuse_existing(path)  # created since it was checked: the same words
            raise
        except OSError as exc:
            raise BadInput(f"cannot write {path}: {exc.strerror or exc}") from None
        self._writer = Writer(self._file, chunk_size=CHUNK_SIZE, compression=CompressionType.ZSTD)
        self._writer.start(profile=PROFILE, library=library)
        self._file.flush()  # the header is on disk at once: even a file killed now is an MCAP file
        self._schemas: dict[str, int] = {}
        self._channels: dict[tuple[str, str, str], int] = {}
        self._chunk_start: int | None = None  # receive time (ns) of the open chunk's first message
        self.messages = 0  # scene messages included
        self.raw = 0  # payloads kept raw (no known type)
        self.closed = False

    @property
    def size(self) -> int:
        """Bytes written to the file so far."""
        return self._file.tell()

    def _channel(self, key: str, msg_type: type[Message] | None, encoding: str) -> int:
        name = type_name(msg_type) if msg_type is not None else ""
        ident = (key, name, "" if msg_type is not None else encoding)
        channel = self._channels.get(ident)
        if channel is None:
            schema = 0  # none: a raw payload
            if msg_type is not None:
                schema = self._schemas.get(name, 0)
                if not schema:
                    import json

                    data = json.dumps(json_schema(msg_type), allow_nan=False).encode()
                    schema = self._schemas[name] = self._writer.register_schema(name, JSON_SCHEMA, data)
            channel = self._writer.register_channel(
                topic=key,
                message_encoding=JSON if msg_type is not None else encoding or "application/octet-stream",
                schema_id=schema,
                metadata={"zenoh_encoding": encoding_for(msg_type) if msg_type is not None else encoding},
            )
            self._channels[ident] = channel
        return channel

    def add(self, key: str, encoding: str, payload: bytes, received: int) -> Message | None:
        """One sample on ``key`` as received at ``received`` (ns since the epoch); the message
        it holds (None if it is kept raw)."""
        self._before_adding(received)
        msg_type = type_from_encoding(encoding)
        message: Message | None = None
        if msg_type is not None:
            try:
                message = decode(payload, msg_type)
            except DecodeError:
                msg_type = None  # garbage under a known type's name: kept as it came
        if message is None:
            self.raw += 1
            channel = self._channel(key, None, encoding)
            self._writer.add_message(channel, log_time=received, publish_time=received, data=payload, sequence=0)
        else:
            stamp = getattr(message, "stamp", 0) or received
            seq = getattr(message, "seq", 0) & 0xFFFFFFFF  # MCAP's sequence is 32 bits
            channel = self._channel(key, type(message), encoding)
            self._writer.add_message(
                channel, log_time=received, publish_time=stamp, data=to_json(message), sequence=seq
            )
        self.messages += 1
        return message

    def add_scene(self, topic: str, drawing: Any, when: int) -> None:
        """A Foxglove well-known message (``drawing``: foxglove.messages) on ``topic`` at ``when``."""
        self._before_adding(when)
        schema = drawing.get_schema()
        ident = (topic, schema.name, PROTOBUF)
        channel = self._channels.get(ident)
        if channel is None:
            sid = self._schemas.get(schema.name, 0) or self._writer.register_schema(schema.name, PROTOBUF, schema.data)
            self._schemas[schema.name] = sid
            channel = self._channels[ident] = self._writer.register_channel(topic, PROTOBUF, sid)
        self._writer.add_message(channel, log_time=when, publish_time=when, data=drawing.encode())
        self.messages += 1

    def attach_world(self, document: bytes, when: int) -> None:
        """Keep the world the run happens in (``turtlectl/world``'s JSON), on disk at once."""
        self._writer.add_attachment(
            create_time=when, log_time=when, name=WORLD, media_type="application/json", data=document
        )
        self._writer.flush()

    def mark_gap(self, lost: int, back: int = 0) -> None:
        """A time without router, from ``lost`` to ``back`` (ns since the epoch; 0: still lost
        at the end), on disk at once."""
        self._writer.add_metadata(GAP, {"lost": str(lost), "back": str(back) if back else ""})
        self._writer.flush()

    def _before_adding(self, received: int) -> None:
        """Close the open chunk if a message received at ``received`` would make it span too long."""
        self.tick(received)
        if self._chunk_start is None:
            self._chunk_start = received

    def tick(self, now: int | None = None) -> None:
        """Close the open chunk, writing it to disk, once its first message is ``CHUNK_SPAN`` old at
        ``now`` (ns since the epoch, as receive times)."""
        now = time.time_ns() if now is None else now
        if self._chunk_start is not None and now - self._chunk_start >= CHUNK_SPAN:
            self._chunk_start = None
            self._writer.flush()  # the chunk, and the file's buffer, written

    def close(self) -> None:
        """Finish the file: the summary section (index, statistics) and the footer."""
        if not self.closed:
            self.closed = True
            self._writer.finish()
            self._file.close()
