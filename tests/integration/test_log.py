"""One log stream: every node publishes each record it logs on turtlectl/log/<node>
and keeps its last ones for a get; ``turtlectl log`` reads every node's in one place, filtered
by --node, --level and --since, and with --follow goes on with the new ones; a node run by
hand (``turtlectl run``) is in the stream as the launched ones are; ``record -a`` keeps them.
(Under --secure: test_security; Foxglove's Log channel: test_foxglove.)"""

from __future__ import annotations

import json
import queue
import signal
import subprocess
import textwrap
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from tests.integration.harness import NODES, turtlectl
from turtlectl.runtime.client.errors import ExitCode

pytestmark = pytest.mark.integration


def records(result: subprocess.CompletedProcess[str]) -> list[dict[str, Any]]:
    assert result.returncode == 0, result.stderr
    return [json.loads(line) for line in result.stdout.splitlines()]


def until(read: Callable[[], list[dict[str, Any]]], wanted: Callable[[list[dict[str, Any]]], bool], what: str):
    """``read()`` again until ``wanted`` holds of what it gives (a record is published as it is
    logged, and a node may log it just after the call that made it answered)."""
    deadline = time.monotonic() + 15.0
    while True:
        got = read()
        if wanted(got):
            return got
        assert time.monotonic() < deadline, f"no {what} within 15 s: {got}"
        time.sleep(0.1)  # pacing: asking the nodes again under a deadline


def messages(got: list[dict[str, Any]], node: str | None = None) -> list[str]:
    return [r["message"] for r in got if node is None or r["node"] == node]


class Lines:
    """A command's stdout, line by line, read on a thread (``next`` waits for one)."""

    def __init__(self, proc: subprocess.Popen[str]):
        self.proc = proc
        self._lines: queue.SimpleQueue[str] = queue.SimpleQueue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self._lines.put(line)

    def until(self, wanted: Callable[[dict[str, Any]], bool], timeout: float = 15.0) -> list[dict[str, Any]]:
        """Every JSON line up to the first that is ``wanted``."""
        seen: list[dict[str, Any]] = []
        deadline = time.monotonic() + timeout
        while not seen or not wanted(seen[-1]):
            remaining = deadline - time.monotonic()
            assert remaining > 0 and self.proc.poll() is None, f"not among {seen} (exit {self.proc.poll()})"
            try:
                seen.append(json.loads(self._lines.get(timeout=min(remaining, 0.5))))
            except queue.Empty:
                continue
        return seen


def test_log_shows_every_nodes_records_filtered_by_node_level_and_time(system):
    everything = records(system.run_cli("log", "--json"))
    ready = {r["node"]: r for r in everything if r["message"].startswith("ready (pid")}
    assert set(ready) == set(NODES), everything  # one place: every node of the launch
    assert all(r["level"] == 20 and r["file"].endswith("lifecycle.py") and r["line"] > 0 for r in ready.values())
    assert [r["stamp"] for r in everything] == sorted(r["stamp"] for r in everything)  # merged by time

    # what a user does makes records: a parameter change (INFO) and a canceled goal (WARNING)
    assert system.run_cli("param", "set", "navigator", "goal_timeout", "45").returncode == 0
    given_up = system.run_cli("goto", "1.5", "1.5", "0", "--timeout", "0.5")  # the navigator cancels it
    assert given_up.returncode == ExitCode.FAILED, given_up.stderr

    navigator = until(
        lambda: records(system.run_cli("log", "--node", "navigator", "--json")),
        lambda got: any("canceled" in m for m in messages(got)),
        "canceled goal in navigator's log",
    )
    assert {r["node"] for r in navigator} == {"navigator"}
    assert "parameter goal_timeout: 30.0 -> 45.0" in messages(navigator)
    changed = next(r for r in navigator if r["message"].startswith("parameter goal_timeout"))

    warnings = records(system.run_cli("log", "--level", "warn", "--json"))
    assert warnings and all(r["level"] >= 30 for r in warnings)
    assert any(
        r["node"] == "navigator" and "goal failed" in r["message"] and "canceled" in r["message"] for r in warnings
    )

    assert {r["node"] for r in records(system.run_cli("log", "--node", "status*", "--node", "sim", "--json"))} == {
        "status_monitor",
        "sim",
    }

    # --since: only what is newer; half-way between the ready lines and the parameter change
    since = (time.time_ns() - (ready["navigator"]["stamp"] + changed["stamp"]) // 2) / 1e9
    recent = records(system.run_cli("log", "--since", f"{since:.3f}s", "--json"))
    assert "parameter goal_timeout: 30.0 -> 45.0" in messages(recent, "navigator")
    assert not any(m.startswith("ready (pid") for m in messages(recent))

    # for people: time, level, node, text, one line each, no colour when piped
    text = system.run_cli("log", "--node", "navigator")
    assert text.returncode == 0 and "\033[" not in text.stdout
    assert any(
        line[12:] == " INFO     navigator: parameter goal_timeout: 30.0 -> 45.0" for line in text.stdout.splitlines()
    ), text.stdout

    nobody = system.run_cli("log", "--node", "nosuch")
    assert nobody.returncode == ExitCode.UNREACHABLE and "no running node matches --node nosuch" in nobody.stderr
    assert "running: navigator, obstacle_detector, sim, status_monitor" in nobody.stderr


def test_follow_prints_the_recent_records_then_each_new_one_once(system):
    follow = subprocess.Popen(
        [*turtlectl(), "log", "-f", "--node", "navigator", "--json", "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        text=True,
    )
    try:
        lines = Lines(follow)
        before = lines.until(lambda r: r["message"].startswith("ready (pid"))  # the recent ones first
        assert {r["node"] for r in before} == {"navigator"}
        assert system.run_cli("param", "set", "navigator", "goal_timeout", "50").returncode == 0
        after = lines.until(lambda r: r["message"].endswith("-> 50.0"))
        seen = before + after
        assert len({(r["stamp"], r["seq"]) for r in seen}) == len(seen)  # each record once
        follow.send_signal(signal.SIGINT)
        assert follow.wait(10) == 0  # Ctrl-C is how --follow ends
    finally:
        if follow.poll() is None:
            follow.kill()
            follow.wait()


CHATTY = textwrap.dedent(
    '''
    """A node run by hand: it logs at start and once from a timer."""

    import msgspec

    from turtlectl import Node, run_main


    class ChattyParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
        pass


    class Chatty:
        Params = ChattyParams

        def __init__(self, node: Node[ChattyParams]):
            self.node = node
            node.log.info("chatty is up")
            self.timer = node.timer(0.2, self.once)

        def once(self) -> None:
            self.timer.undeclare()
            self.node.log.warning("chatty warns once")


    if __name__ == "__main__":
        run_main(Chatty, ChattyParams)
    '''
)


def test_a_hand_run_nodes_records_are_in_the_stream(system, tmp_path: Path):
    (tmp_path / "chatty.py").write_text(CHATTY)
    run = subprocess.Popen(
        [*turtlectl(), "run", "./chatty.py:Chatty", "--connect", system.endpoint],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        stdin=subprocess.DEVNULL,
        text=True,
    )
    try:
        system.wait_until(lambda: "chatty" in system.alive or run.poll() is not None, 30.0, "turtlectl run")
        assert run.poll() is None, run.communicate()[0]
        chatty = until(
            lambda: records(system.run_cli("log", "--node", "chatty", "--json")),
            lambda got: "chatty warns once" in messages(got),
            "record of the hand-run node",
        )
        assert messages(chatty)[:2] == ["chatty is up", f"ready (pid {system.alive['chatty']})"]
        assert chatty[0]["file"].endswith("chatty.py") and chatty[0]["function"] == "__init__"
        warned = records(system.run_cli("log", "--node", "chatty", "--level", "WARNING", "--json"))
        assert messages(warned) == ["chatty warns once"]
        # in one place with the launched nodes'
        assert {"chatty", *NODES} <= {r["node"] for r in records(system.run_cli("log", "--json"))}
        run.send_signal(signal.SIGINT)
        out, _ = run.communicate(timeout=10)
        assert run.returncode == 0, out
        assert "INFO chatty is up" in out  # its own terminal still has it
    finally:
        if run.poll() is None:
            run.kill()
            run.wait()


def test_record_keeps_the_log_like_any_topic(system, tmp_path: Path):
    from turtlectl.cli.recording.reading import Recording

    path = tmp_path / "log.mcap"
    recorder = subprocess.Popen(
        [*turtlectl(), "record", "-a", "-o", str(path), "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        text=True,
    )
    try:
        deadline = time.monotonic() + 15.0
        while not (path.exists() and Recording(path).info().count > 20):  # it records: its subscriber is there
            assert time.monotonic() < deadline and recorder.poll() is None, "the recorder wrote nothing"
            time.sleep(0.05)  # pacing: polling a file under a deadline
        assert system.run_cli("param", "set", "navigator", "goal_timeout", "55").returncode == 0
        logged = until(
            lambda: records(system.run_cli("log", "--node", "navigator", "--json")),
            lambda got: any(m.endswith("-> 55.0") for m in messages(got)),
            "the parameter change in the log",
        )
        changed = next(r for r in logged if r["message"].endswith("-> 55.0"))
        recorder.send_signal(signal.SIGINT)
        _, err = recorder.communicate(timeout=15)
        assert recorder.returncode == 0, err
    finally:
        if recorder.poll() is None:
            recorder.kill()
            recorder.wait()
    shown = subprocess.run([*turtlectl(), "info", str(path), "--json"], capture_output=True, text=True, timeout=30)
    topics = {t["key"]: t for t in json.loads(shown.stdout)["topics"]}
    assert topics["turtlectl/log/navigator"]["type_name"] == "turtlectl/Log", sorted(topics)
    kept = [r.message() for r in Recording(path).records() if r.key == "turtlectl/log/navigator"]
    assert any(m.message == changed["message"] and m.stamp == changed["stamp"] for m in kept)
