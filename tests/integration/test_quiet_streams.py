"""`hz` and `echo` when a stream stops, and when the system goes away, against the real
system: `hz` does not print its last rate long after a topic stopped (nor after the system
stopped); `echo` says so once the system went away rather than wait silently, and gives its
silence hint for a topic that stopped as for one on which nothing ever arrived."""

from __future__ import annotations

import json
import queue
import signal
import subprocess
import threading
import time

import pytest

from tests.integration.harness import running_system, turtlectl

pytestmark = pytest.mark.integration


class Watched:
    """A turtlectl command in the background whose stdout and stderr lines are timestamped
    as they arrive (monotonic s), so a test can tell what was printed when."""

    def __init__(self, endpoint: str, *args: str):
        self.proc = subprocess.Popen(
            [*turtlectl(), *args, "--connect", endpoint],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            stdin=subprocess.DEVNULL,
            text=True,
        )
        self.out: queue.SimpleQueue[tuple[float, str]] = queue.SimpleQueue()
        self.err: queue.SimpleQueue[tuple[float, str]] = queue.SimpleQueue()
        self.readers = [
            threading.Thread(target=self._read, args=(stream, lines), daemon=True)
            for stream, lines in ((self.proc.stdout, self.out), (self.proc.stderr, self.err))
        ]
        for reader in self.readers:
            reader.start()

    @staticmethod
    def _read(stream, lines: queue.SimpleQueue) -> None:
        for line in stream:
            lines.put((time.monotonic(), line.rstrip("\n")))

    @staticmethod
    def next_line(lines: queue.SimpleQueue, timeout: float, contains: str = "") -> tuple[float, str]:
        """The next line (containing ``contains``) within ``timeout`` s: an event, not a sleep."""
        deadline = time.monotonic() + timeout
        while True:
            try:
                at, line = lines.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                raise AssertionError(f"no line with {contains!r} within {timeout} s") from None
            if contains in line:
                return at, line

    def drained(self, lines: queue.SimpleQueue) -> list[tuple[float, str]]:
        got = []
        while not lines.empty():
            got.append(lines.get())
        return got

    def finish(self, timeout: float) -> int:
        code = self.proc.wait(timeout)
        for reader in self.readers:
            reader.join(5)
        return code

    def kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(5)


def _publish(endpoint: str, key: str, times: int) -> float:
    """Publish ``times`` Twists at 20 Hz on ``key``; returns when the publisher ended."""
    done = subprocess.run(
        [*turtlectl(), "pub", key, '{"linear": 0.0}', "--type", "Twist", "--rate", "20", "--times", str(times)]
        + ["--connect", endpoint],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert done.returncode == 0, done.stderr
    return time.monotonic()


def test_hz_stops_reporting_a_topic_that_stopped_and_says_why_echo_gives_the_same_hint(system):
    hz = Watched(system.endpoint, "hz", "test/quiet", "--json")
    echo = Watched(system.endpoint, "echo", "test/quiet", "--field", "linear")
    try:
        first, _ = Watched.next_line(hz.err, 15.0, "nothing published on test/quiet yet")  # both are listening
        Watched.next_line(echo.err, 15.0, "nothing published on test/quiet yet")
        ended = _publish(system.endpoint, "test/quiet", 60)  # 3 s at 20 Hz
        rates = [json.loads(line)["rate"] for _, line in hz.drained(hz.out)]
        assert rates and abs(rates[-1] - 20.0) < 1.0, rates
        said, line = Watched.next_line(hz.err, 10.0, "test/quiet")
        assert line == (
            "nothing published on test/quiet for 3 s: no running node publishes it (`turtlectl list` shows the topics)"
        )
        assert said - ended > 2.5, "said before 3 s of silence"
        late = [(round(at - ended, 2), text) for at, text in hz.drained(hz.out) if at > ended + 1.2]
        assert not late, f"hz kept printing a rate after the topic stopped: {late}"
        hinted, hint = Watched.next_line(echo.err, 5.0, "test/quiet")
        assert hint == line and hinted - ended > 2.5
        assert len(echo.drained(echo.out)) == 60  # every message printed, then the hint
        for command in (hz, echo):
            command.proc.send_signal(signal.SIGINT)
            assert command.finish(10) == 0
    finally:
        hz.kill()
        echo.kill()


def test_hz_and_echo_with_exit_on_loss_report_the_system_going_away_as_goto_does():
    with running_system() as system:
        hz = Watched(system.endpoint, "hz", "robot/status", "--exit-on-loss")
        echo = Watched(system.endpoint, "echo", "robot/status", "--field", "x", "--exit-on-loss")
        try:
            Watched.next_line(hz.out, 15.0)  # both are receiving
            Watched.next_line(echo.out, 15.0)
            assert system.stop() == 0
            stopped = time.monotonic()
            for command in (hz, echo):
                assert command.finish(10) == 3
                assert time.monotonic() - stopped < 5.0
            lost = f"turtlectl: error: lost the router at {system.endpoint}: no more messages on robot/status"
            for command in (hz, echo):
                errors = [text for _, text in command.drained(command.err)]
                assert errors[-1] == lost + " (did `turtlectl launch` stop?)", errors
            late = [text for at, text in hz.drained(hz.out) if at > stopped + 1.2]
            assert not late, f"hz kept printing a rate after the system stopped: {late}"
        finally:
            hz.kill()
            echo.kill()
