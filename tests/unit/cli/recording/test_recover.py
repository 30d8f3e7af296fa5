"""cli.recording.recover: a recording that was never closed (cut as a SIGKILL leaves it) is written again
whole and indexed, so that an indexed MCAP reader opens it; nothing existing is overwritten."""

from __future__ import annotations

import pytest

from turtlectl.cli.recording.bag import BagWriter, RecordingError
from turtlectl.cli.recording.reading import Recording
from turtlectl.cli.recording.recover import default_output, hint, recover, text
from turtlectl.messages import Pose, TurtleStatus, encode, encoding_for
from turtlectl.runtime.client.errors import BadInput

T0 = 1_700_000_000_000_000_000
STEP = 10_000_000  # ns: 100 messages a second


def _killed(path, seconds: float = 3.0) -> int:
    """A recording of ``seconds`` s of poses, a status, a raw payload and the world, left as a
    SIGKILL leaves it: never closed, cut in the middle of the chunk being written.  Returns
    how many poses the complete chunks hold."""
    whole = path.with_name("whole.mcap")
    writer = BagWriter(whole)
    writer.attach_world(b'{"size": 11.0, "obstacles": []}', T0)
    writer.add("raw/bytes", "zenoh/bytes", b"\x00\x01", T0)
    writer.add(
        "robot/status",
        encoding_for(TurtleStatus),
        encode(TurtleStatus(x=1, y=2, theta=3, vel_x=0, vel_y=0, battery=50)),
        T0,
    )
    for i in range(int(seconds / STEP * 1e9)):
        writer.add("turtle1/pose", encoding_for(Pose), encode(Pose(x=float(i), y=0.0, theta=0.0, seq=i)), T0 + i * STEP)
    data = whole.read_bytes()  # as the recorder left it: the open chunk not written yet
    size = len(data)
    writer.close()
    path.write_bytes(data + whole.read_bytes()[size : size + 200])  # and a chunk cut while being written
    return sum(1 for r in Recording(path).records() if r.key == "turtle1/pose")


def test_a_file_that_was_not_closed_is_written_whole_and_indexed(tmp_path):
    from mcap.reader import make_reader

    source = tmp_path / "run.mcap"
    poses = _killed(source)
    assert poses >= 200 and not Recording(source).closed
    with open(source, "rb") as f, pytest.raises(Exception):  # noqa: B017 - whatever the indexed reader raises
        list(make_reader(f).iter_messages())  # what Foxglove and the reference reader refuse
    done = recover(source)
    assert done.output == tmp_path / "run-recovered.mcap" and not done.closed
    assert done.messages == poses + 2 and done.attachments == 1
    with open(done.output, "rb") as f:
        reader = make_reader(f)
        assert reader.get_summary() is not None
        read = [(channel.topic, message.sequence) for _, channel, message in reader.iter_messages()]
    assert [s for topic, s in read if topic == "turtle1/pose"] == list(range(poses))
    assert {topic for topic, _ in read} == {"turtle1/pose", "robot/status", "raw/bytes"}
    recovered = Recording(done.output)
    assert recovered.closed and recovered.world() == b'{"size": 11.0, "obstacles": []}'
    assert [r.message() for r in recovered.records()] == [r.message() for r in Recording(source).records()]
    assert done.duration == pytest.approx((poses - 1) * STEP / 1e9)
    assert "recovered" in text(done) and str(done.output) in text(done)


def test_an_existing_output_is_never_overwritten_nor_the_source(tmp_path):
    source = tmp_path / "run.mcap"
    _killed(source, 0.5)
    taken = tmp_path / "taken.mcap"
    taken.write_bytes(b"precious")
    with pytest.raises(BadInput, match="already exists"):
        recover(source, taken)
    assert taken.read_bytes() == b"precious"
    with pytest.raises(BadInput, match="the file being recovered"):
        recover(source, source)
    before = source.read_bytes()
    done = recover(source, tmp_path / "copy.mcap")
    assert done.output.exists() and source.read_bytes() == before


def test_a_closed_file_is_copied_and_says_so(tmp_path):
    source = tmp_path / "closed.mcap"
    writer = BagWriter(source)
    writer.add("turtle1/pose", encoding_for(Pose), encode(Pose(x=1.0, y=0.0, theta=0.0)), T0)
    writer.close()
    done = recover(source)
    assert done.closed and done.messages == 1 and "complete already" in text(done)


def test_what_is_not_a_recording_is_refused(tmp_path):
    notes = tmp_path / "notes.txt"
    notes.write_text("hello")
    with pytest.raises(RecordingError, match="not an MCAP file"):
        recover(notes)
    with pytest.raises(RecordingError, match="no such file"):
        recover(tmp_path / "missing.mcap")
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(b"\x89MCAP0\r\n\x01\x00")
    with pytest.raises(RecordingError, match="truncated"):
        recover(cut)
    assert not (tmp_path / "cut-recovered.mcap").exists()


def test_the_default_output_and_the_hint():
    from pathlib import Path

    assert default_output(Path("a/run.mcap")) == Path("a/run-recovered.mcap")
    assert default_output(Path("run")) == Path("run-recovered.mcap")
    assert hint(Path("my run.mcap")).startswith("`turtlectl recover 'my run.mcap'`")
