"""cli.recording.bag with real files: what is written reads back (typed messages equal, raw payloads as
they came, times and sequence numbers kept); a file never closed reads up to its last complete
chunk and says so; files that are not recordings are refused with one clear error (exit 2)."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import textwrap

import pytest

from tests.unit.messages.samples import SAMPLES as WRITTEN
from turtlectl.cli.recording.bag import BagWriter, RecordingError
from turtlectl.cli.recording.reading import Recording
from turtlectl.messages import LaserScan, Pose, TurtleStatus, decode_any, encode, encoding_for
from turtlectl.runtime.client.errors import ExitCode, exit_code

SAMPLES = [decode_any(encode(m)) for m in WRITTEN]  # as received: floats where the samples wrote ints

T0 = 1_700_000_000_000_000_000


def _pose(i: int) -> Pose:
    return Pose(x=float(i), y=1.0, theta=0.5, stamp=T0 + i * 16_000_000, seq=i)


def test_typed_and_raw_messages_read_back_as_written(tmp_path):
    path = tmp_path / "run.mcap"
    writer = BagWriter(path)
    for i, msg in enumerate(SAMPLES):
        writer.add(f"k/{i}", encoding_for(type(msg)), encode(msg), T0 + i)
    writer.add("raw/bytes", "zenoh/bytes", b"\x00\x01", T0 + 100)
    writer.add("turtle1/pose", encoding_for(Pose), b"garbage", T0 + 101)  # named Pose, but not one
    writer.close()
    recording = Recording(path)
    assert recording.closed
    records = list(recording.records())
    assert [encode(r.message()) for r in records[: len(SAMPLES)]] == [encode(m) for m in SAMPLES]
    assert [r.type_name for r in records[: len(SAMPLES)]] == [type(m).__struct_config__.tag for m in SAMPLES]
    raw = records[len(SAMPLES) :]
    assert [(r.key, r.type_name, r.encoding, r.data) for r in raw] == [
        ("raw/bytes", "", "zenoh/bytes", b"\x00\x01"),
        ("turtle1/pose", "", encoding_for(Pose), b"garbage"),
    ]
    assert all(r.message() is None for r in raw)
    pose = records[1]
    assert (pose.log_time, pose.publish_time, pose.sequence) == (T0 + 1, SAMPLES[1].stamp, SAMPLES[1].seq)


def test_info_counts_each_topic_with_its_type_rate_and_encoding(tmp_path):
    path = tmp_path / "run.mcap"
    writer = BagWriter(path)
    for i in range(63):  # 62 intervals of 16 ms: 0.992 s
        writer.add("turtle1/pose", encoding_for(Pose), encode(_pose(i)), T0 + i * 16_000_000)
    status = TurtleStatus(x=1, y=2, theta=3, vel_x=0, vel_y=0, battery=50)
    writer.add("robot/status", encoding_for(TurtleStatus), encode(status), T0 + 500_000_000)
    writer.close()
    info = Recording(path).info()
    assert info.closed and info.count == 64 and info.size == path.stat().st_size
    assert info.start == T0 and info.end == T0 + 62 * 16_000_000
    topics = {t.key: t for t in info.topics}
    assert topics["turtle1/pose"].type_name == "turtlectl/Pose" and topics["turtle1/pose"].count == 63
    assert topics["turtle1/pose"].encoding == "json"
    assert topics["turtle1/pose"].rate == pytest.approx(63 / 0.992)


def test_the_schema_in_the_file_is_the_types_json_schema(tmp_path):
    from mcap.reader import make_reader

    path = tmp_path / "run.mcap"
    writer = BagWriter(path)
    writer.add("obstacles", encoding_for(LaserScan), encode(SAMPLES[3]), T0)
    writer.close()
    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
    (schema,) = summary.schemas.values()
    (channel,) = summary.channels.values()
    assert (schema.name, schema.encoding, channel.message_encoding) == ("turtlectl/LaserScan", "jsonschema", "json")
    assert json.loads(schema.data)["title"] == "turtlectl/LaserScan"
    assert channel.topic == "obstacles"


KILLED_WRITER = textwrap.dedent(
    """
    import os, sys, time
    from pathlib import Path
    from turtlectl.cli.recording.bag import BagWriter
    from turtlectl.messages import Pose, encode, encoding_for
    writer = BagWriter(Path(sys.argv[1]))
    start = time.monotonic()
    i = 0
    while time.monotonic() - start < 2.5:
        writer.add("turtle1/pose", encoding_for(Pose), encode(Pose(x=float(i), y=0.0, theta=0.0, seq=i)), time.time_ns())
        writer.tick()
        i += 1
        time.sleep(0.01)  # pacing: about 100 messages a second
    print(i, flush=True)
    os.kill(os.getpid(), 9)
    """
)


def test_a_killed_recorder_leaves_every_message_but_the_last_second(tmp_path):
    path = tmp_path / "killed.mcap"
    root = os.path.dirname(
        os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    )
    done = subprocess.run([sys.executable, "-c", KILLED_WRITER, str(path)], cwd=root, capture_output=True, text=True)
    assert done.returncode == -9, done.stderr
    written = int(done.stdout)
    recording = Recording(path)
    assert not recording.closed
    seqs = [r.message().seq for r in recording.records()]
    assert seqs == list(range(len(seqs)))  # what is there is whole and in order
    assert written - len(seqs) <= 110  # at most about one second of ~100 messages a second is lost
    assert len(seqs) >= 100
    info = recording.info()
    assert not info.closed and info.count == len(seqs)


def test_files_that_are_no_recordings_are_refused_with_one_clear_error(tmp_path):
    not_mcap = tmp_path / "notes.txt"
    not_mcap.write_text("hello")
    with pytest.raises(RecordingError, match="is not an MCAP file") as refused:
        Recording(not_mcap)
    assert exit_code(refused.value) == ExitCode.BAD_INPUT
    with pytest.raises(RecordingError, match="no such file"):
        Recording(tmp_path / "missing.mcap")

    whole = tmp_path / "whole.mcap"
    writer = BagWriter(whole)
    writer.add("turtle1/pose", encoding_for(Pose), encode(_pose(0)), T0)
    writer.close()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(whole.read_bytes()[:12])
    with pytest.raises(RecordingError, match="truncated"):
        Recording(cut)


def test_a_channel_of_an_unknown_type_is_refused_naming_it(tmp_path):
    from mcap.writer import Writer

    path = tmp_path / "foreign.mcap"
    with open(path, "wb") as f:
        writer = Writer(f)
        writer.start()
        schema = writer.register_schema("Odometry", "jsonschema", b"{}")
        channel = writer.register_channel("odom", "json", schema)
        writer.add_message(channel, log_time=T0, publish_time=T0, data=b"{}")
        writer.finish()
    with pytest.raises(
        RecordingError, match=r"channel odom has an unknown type \(Odometry\); turtlectl knows (\S+, )*turtlectl/Ack, "
    ):
        Recording(path)


def test_an_existing_file_is_never_overwritten(tmp_path):
    path = tmp_path / "run.mcap"
    path.write_bytes(b"precious")
    with pytest.raises(RecordingError.__mro__[1], match="already exists"):
        BagWriter(path)
    assert path.read_bytes() == b"precious"
    assert math.isfinite(1.0)


def _chunks(data: bytes) -> list:
    """The complete chunks of an MCAP file's bytes (a file still being written included)."""
    import io

    from mcap.records import Chunk
    from mcap.stream_reader import StreamReader

    chunks = []
    try:
        for record in StreamReader(io.BytesIO(data), emit_chunks=True).records:
            if isinstance(record, Chunk):
                chunks.append(record)
    except Exception:  # noqa: BLE001 - the cut end of a file being written
        pass
    return chunks


def test_a_chunk_closes_on_the_messages_own_times_so_at_most_a_second_is_ever_unwritten(tmp_path):
    # messages received every 10 ms over 5 s, some queued (written late): what is on disk at any
    # moment (a SIGKILL then) holds everything received more than a second before the last one
    path = tmp_path / "run.mcap"
    writer = BagWriter(path)
    step = 10_000_000
    for i in range(500):
        writer.add("turtle1/pose", encoding_for(Pose), encode(_pose(i)), T0 + i * step)
        on_disk = _chunks(path.read_bytes())
        written = max((c.message_end_time for c in on_disk), default=T0 - step)
        assert T0 + i * step - written <= 1_000_000_000, f"{(T0 + i * step - written) / 1e9:.2f} s unwritten"
    spans = [(c.message_end_time - c.message_start_time) / 1e9 for c in _chunks(path.read_bytes())]
    assert spans and max(spans) < 1.0, spans
    writer.close()


def test_tick_closes_a_chunk_whose_first_message_is_old_enough(tmp_path):
    path = tmp_path / "run.mcap"
    writer = BagWriter(path)
    writer.add("turtle1/pose", encoding_for(Pose), encode(_pose(0)), T0)
    writer.tick(T0 + 500_000_000)
    assert _chunks(path.read_bytes()) == []  # half a second: still open
    writer.tick(T0 + 1_000_000_000)
    assert len(_chunks(path.read_bytes())) == 1
    writer.close()


def test_scene_messages_are_counted_with_the_others(tmp_path):
    from turtlectl.cli.foxglove.scene import SceneMaker
    from turtlectl.messages.world import World

    path = tmp_path / "run.mcap"
    writer = BagWriter(path)
    writer.add("turtle1/pose", encoding_for(Pose), encode(_pose(0)), T0)
    topic, drawn = SceneMaker(World()).world_update(T0)
    writer.add_scene(topic, drawn, T0 + 1)
    writer.close()
    assert writer.messages == Recording(path).info().count == 2


def test_a_gap_without_router_is_marked_info_lists_it_and_the_messages_read_past_it(tmp_path):
    from turtlectl.cli.tools.format import info_text

    path = tmp_path / "gap.mcap"
    writer = BagWriter(path)
    writer.add("turtle1/pose", encoding_for(Pose), encode(_pose(0)), T0)
    writer.mark_gap(T0 + 1_000_000_000, T0 + 3_500_000_000)
    writer.add("turtle1/pose", encoding_for(Pose), encode(_pose(1)), T0 + 4_000_000_000)
    writer.mark_gap(T0 + 5_000_000_000)  # still lost when the recording ended
    writer.add("turtle1/pose", encoding_for(Pose), encode(_pose(2)), T0 + 6_000_000_000)
    writer.close()
    recording = Recording(path)
    assert [r.message().seq for r in recording.records()] == [0, 1, 2]
    info = recording.info()
    assert [(g.lost - T0, g.back - T0 if g.back else 0, g.duration) for g in info.gaps] == [
        (1_000_000_000, 3_500_000_000, 2.5),
        (5_000_000_000, 0, 1.0),
    ]
    text = info_text(info)
    assert "2.5 s, nothing recorded" in text and "until the end (never back): 1.0 s" in text


def test_a_gap_of_a_file_never_closed_is_listed_too(tmp_path):
    path = tmp_path / "killed.mcap"
    writer = BagWriter(path)
    writer.add("turtle1/pose", encoding_for(Pose), encode(_pose(0)), T0)
    writer.mark_gap(T0 + 1_000_000_000, T0 + 2_000_000_000)
    writer.add("turtle1/pose", encoding_for(Pose), encode(_pose(1)), T0 + 3_000_000_000)
    writer.tick(T0 + 4_000_000_000)  # the chunk on disk; the file is never closed
    info = Recording(path).info()
    assert not info.closed and [g.duration for g in info.gaps] == [1.0]
