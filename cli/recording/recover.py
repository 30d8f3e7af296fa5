"""``turtlectl recover``: a recording the recorder never finished (killed with SIGKILL, the
machine lost power), written again whole and indexed, as ``mcap recover`` and ``ros2 bag
reindex`` do.  Nothing here prints.

A file that was not closed has no summary section and no footer: a streaming reader gets its
complete chunks, but an indexed reader (Foxglove, mcap's ``make_reader``, most tools) refuses
it.  ``recover`` reads it as a stream up to the first damage (the chunk being written when the
recorder died) and writes every schema, channel, message, attachment and metadata record it
got into a new file, with chunk and message indexes, statistics and footer.  The source is
never changed and an existing file is never overwritten.
"""

from __future__ import annotations

import dataclasses
import shlex
from pathlib import Path
from typing import Any

from turtlectl.cli.recording.bag import CHUNK_SIZE, RecordingError
from turtlectl.cli.recording.reading import read_errors
from turtlectl.runtime.client.errors import BadInput

MAGIC = b"\x89MCAP0\r\n"


@dataclasses.dataclass(frozen=True)
class Recovered:
    source: Path
    output: Path
    messages: int
    attachments: int
    start: int  # ns since the epoch of the first message (0 when none)
    end: int  # of the last
    closed: bool  # the source was complete already (it had its summary): the output is a copy
    damage: str  # why reading stopped before the end ("" when it did not)

    @property
    def duration(self) -> float:
        return (self.end - self.start) / 1e9


def default_output(path: Path) -> Path:
    """``run.mcap`` -> ``run-recovered.mcap``, beside it."""
    stem = path.stem if path.suffix == ".mcap" else path.name
    return path.with_name(f"{stem}-recovered.mcap")


def hint(path: Path | str) -> str:
    """What to do with a file that was not closed (for ``info`` and ``play``)."""
    return f"`turtlectl recover {shlex.quote(str(path))}` writes a complete, indexed copy that every MCAP reader opens"


def recover(source: Path, output: Path | None = None) -> Recovered:
    """Write everything readable of ``source`` into ``output`` (default: ``default_output``),
    indexed.  Raises RecordingError for a source that is not an MCAP file (or has no readable
    header), BadInput when ``output`` exists or cannot be written."""
    output = default_output(source) if output is None else output
    _check_source(source)
    if output.resolve() == source.resolve():
        raise BadInput(f"{output} is the file being recovered: write the copy to another file with -o")
    try:
        out = open(output, "xb")  # noqa: SIM115 - closed below
    except FileExistsError:
        raise BadInput(f"{output} already exists (it is never overwritten): choose another name with -o") from None
    except OSError as exc:
        raise BadInput(f"cannot write {output}: {exc.strerror or exc}") from None
    try:
        with out, open(source, "rb") as f:
            return _copy(source, output, f, out)
    except BaseException:
        output.unlink(missing_ok=True)  # nothing half-written is left behind
        raise


def _check_source(source: Path) -> None:
    try:
        with open(source, "rb") as f:
            magic = f.read(len(MAGIC))
    except FileNotFoundError:
        raise RecordingError(f"{source}: no such file") from None
    except OSError as exc:
        raise RecordingError(f"cannot read {source}: {exc.strerror or exc}") from None
    if magic != MAGIC:
        raise RecordingError(f"{source} is not an MCAP file (a recording made by `turtlectl record`)")


def _copy(source: Path, output: Path, f: Any, out: Any) -> Recovered:
    from mcap.records import Attachment, Channel, DataEnd, Footer, Header, Message, Metadata, Schema
    from mcap.stream_reader import StreamReader
    from mcap.writer import CompressionType, Writer

    records = iter(StreamReader(f, validate_crcs=True).records)
    errors = read_errors()
    writer = Writer(out, chunk_size=CHUNK_SIZE, compression=CompressionType.ZSTD)
    schemas: dict[int, int] = {0: 0}  # id in the source -> id in the output (0: no schema)
    channels: dict[int, int] = {}
    started = closed = False
    damage = ""
    messages = attachments = start = end = 0
    while True:
        try:
            record = next(records, None)
        except errors as exc:
            damage = str(exc) or type(exc).__name__
            break
        if record is None or isinstance(record, (DataEnd, Footer)):
            closed = record is not None
            break
        if isinstance(record, Header):
            writer.start(profile=record.profile, library=record.library)
            started = True
        elif not started:
            break  # no header first: not readable as a recording
        elif isinstance(record, Schema) and record.id not in schemas:
            schemas[record.id] = writer.register_schema(record.name, record.encoding, record.data)
        elif isinstance(record, Channel) and record.id not in channels and record.schema_id in schemas:
            channels[record.id] = writer.register_channel(
                record.topic, record.message_encoding, schemas[record.schema_id], dict(record.metadata)
            )
        elif isinstance(record, Message) and record.channel_id in channels:
            writer.add_message(
                channels[record.channel_id],
                log_time=record.log_time,
                data=record.data,
                publish_time=record.publish_time,
                sequence=record.sequence,
            )
            messages += 1
            start = record.log_time if messages == 1 else min(start, record.log_time)
            end = max(end, record.log_time)
        elif isinstance(record, Attachment):
            writer.add_attachment(record.create_time, record.log_time, record.name, record.media_type, record.data)
            attachments += 1
        elif isinstance(record, Metadata):
            writer.add_metadata(record.name, dict(record.metadata))
    if not started:
        raise RecordingError(f"{source} is truncated: not even its header can be read")
    writer.finish()
    return Recovered(source, output, messages, attachments, start, end, closed, damage)


def text(done: Recovered) -> str:
    """One line saying what was recovered."""
    what = f"{done.messages} messages ({done.duration:.3f} s)" + (
        f" and {done.attachments} attachment{'s' * (done.attachments != 1)}" if done.attachments else ""
    )
    line = f"recovered {what} from {done.source} into {done.output}"
    if done.closed:
        return line + f" ({done.source} was complete already: this is an indexed copy)"
    return line + " (what followed the last complete chunk was lost when the recorder stopped)"
