"""Benchmark of record and play, on the real system in one run.

1. Recorder at full rate: the default system runs goals back to back (every topic at its
   full rate: 62.5 Hz poses, 10 Hz status, 5 Hz scans, and feedback and cmd_vel while goals
   run) while `turtlectl record -a` records for --minutes and a subscriber in this process
   notes every seq it sees.  Reports per key the messages recorded, seq gaps in the file
   that the subscriber saw (lost by the recorder: must be 0) and gaps neither saw (lost on
   the wire), and the recorder's CPU and RSS.
2. Play timing: the first --play-minutes of that recording played into a router without a
   system at rate 1 and at rate 10 (cli.recording.play.play, the code `turtlectl play` runs);
   |actual - scheduled| per message: p50, p99, max.

Usage: python bench/recording.py [--minutes 10] [--play-minutes 5] [--file PATH] [--play-only]
"""

from __future__ import annotations

import argparse
import collections
import itertools
import random
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import psutil

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from bench.system import goal, machine, random_goal, summary  # noqa: E402
from tests.integration.harness import Router, System, turtlectl  # noqa: E402
from turtlectl.cli.recording.bag import Record  # noqa: E402
from turtlectl.cli.recording.play import play  # noqa: E402
from turtlectl.cli.recording.reading import Recording  # noqa: E402
from turtlectl.messages import Reset, decode_any  # noqa: E402
from turtlectl.messages.keys import RESET  # noqa: E402


class FirstMinutes:
    """The first ``minutes`` of a recording, for the player."""

    def __init__(self, recording: Recording, minutes: float):
        self.recording = recording
        self.path = recording.path
        self.minutes = minutes

    def records(self, keys: list[str] | None = None) -> Iterator[Record]:
        records = self.recording.records(keys)
        first = next(records, None)
        if first is None:
            return
        yield first
        end = first.log_time + int(self.minutes * 60e9)
        yield from itertools.takewhile(lambda r: r.log_time <= end, records)

    def world(self) -> bytes | None:
        return self.recording.world()


def record_at_full_rate(minutes: float, path: Path) -> None:
    system = System()
    try:
        system.wait_ready()
        seen: dict[str, set[int]] = collections.defaultdict(set)
        assert system.session is not None
        sub = system.session.declare_subscriber(
            "**", lambda s: seen[str(s.key_expr)].add(decode_any(s.payload.to_bytes()).seq)
        )
        recorder = subprocess.Popen(
            [*turtlectl(), "record", "-a", "-o", str(path), "--connect", system.endpoint],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        proc = psutil.Process(recorder.pid)
        proc.cpu_percent(None)
        rng = random.Random(11)
        goals = failures = 0
        started = time.monotonic()
        while time.monotonic() - started < minutes * 60:
            response, _ = goal(system, *random_goal(rng, system))
            goals += 1
            if response is None or not response.success:
                failures += 1
                if response is not None and response.reason == "battery low":
                    system.call(RESET, Reset(), everyone=True)
        cpu = proc.cpu_percent(None)
        rss = proc.memory_info().rss / 2**20
        recorder.send_signal(signal.SIGINT)
        recorder.communicate(timeout=30)
        sub.undeclare()
    finally:
        system.stop()
        system.kill_everything()

    recording = Recording(path)
    recorded: dict[str, list[int]] = collections.defaultdict(list)
    for record in recording.records():
        message = record.message()
        recorded[record.key].append(getattr(message, "seq", 0))
    info = recording.info()
    print(
        f"recorded {info.count} messages in {info.duration:.0f} s ({goals} goals, {failures} not reached), "
        f"file {info.size / 2**20:.1f} MiB, closed: {info.closed}"
    )
    print(f"recorder: CPU {cpu:.1f} % of one core over the run, RSS {rss:.0f} MiB")
    print("key                    recorded   lost by the recorder   lost on the wire (seen by neither)")
    for key in sorted(recorded):
        seqs = recorded[key]
        in_file = set(seqs)
        missing = [s for s in range(min(seqs), max(seqs) + 1) if s not in in_file]
        by_recorder = [s for s in missing if s in seen[key]]
        print(f"{key:22s} {len(seqs):9d} {len(by_recorder):22d} {len(missing) - len(by_recorder):20d}")


def play_timing(path: Path, minutes: float) -> None:
    recording = Recording(path)
    router = Router()
    router.start()
    try:
        for rate in (1.0, 10.0):
            stop = threading.Event()
            lates = [
                abs(p.late)
                for p in play(
                    router.endpoint,
                    FirstMinutes(recording, minutes),  # type: ignore[arg-type]
                    rate,
                    0.0,
                    None,
                    {},
                    False,
                    False,
                    lambda: False,
                    stop.is_set,
                )
            ]
            print(f"play at rate {rate:g} ({minutes:g} min recorded): |actual - scheduled| {summary(lates, 'ms', 1e3)}")
    finally:
        router.kill()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--minutes", type=float, default=10.0, help="how long to record at full rate")
    ap.add_argument("--play-minutes", type=float, default=5.0, help="how much of it to play at each rate")
    ap.add_argument("--file", type=Path, help="keep the recording here (default: a temporary file)")
    ap.add_argument("--play-only", action="store_true", help="only play --file, recorded before")
    args = ap.parse_args()
    print(f"machine: {machine()}")
    with tempfile.TemporaryDirectory() as folder:
        path = args.file or Path(folder) / "full_rate.mcap"
        if not args.play_only:
            record_at_full_rate(args.minutes, path)
        play_timing(path, min(args.play_minutes, args.minutes))


if __name__ == "__main__":
    main()
