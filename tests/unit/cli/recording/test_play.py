"""What ``play`` publishes for a recorded message (cli.recording.play._payload)."""

from __future__ import annotations

import msgspec

from turtlectl.cli.recording.bag import Record
from turtlectl.cli.recording.play import _payload
from turtlectl.messages import Log, TurtleStatus, decode_any


def record_of(message: msgspec.Struct, log_time: int = 5_000) -> Record:
    return Record("k", type(message).__struct_config__.tag, "", log_time, 0, 0, msgspec.json.encode(message))


def test_messages_are_stamped_when_sent_but_a_log_record_keeps_when_it_was_logged():
    """Replayed log records keep their recorded stamps: stamped with the replay's time they would
    read as live records of a node that is not there."""
    status = TurtleStatus(x=1, y=2, theta=0, vel_x=0, vel_y=0, battery=50, stamp=7)
    sent, _ = _payload(record_of(status), status, keep_stamps=False)
    assert decode_any(sent).stamp > 7
    log = Log(level=30, node="navigator", message="goal canceled", stamp=7)
    sent, _ = _payload(record_of(log), log, keep_stamps=False)
    assert decode_any(sent).stamp == 7
    sent, _ = _payload(record_of(log), log, keep_stamps=False, recorded=True)  # play --clock too
    assert decode_any(sent).stamp == 7
