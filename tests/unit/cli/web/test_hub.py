"""The hub: which turtle a sample is about, the newest of each per page version (never a backlog),
rates on a fake clock, log records and watched topics."""

from __future__ import annotations

from typing import Any

from turtlectl.cli.web.hub import Hub, turtle_and_section
from turtlectl.messages import LaserScan, Log, NavigateToFeedback, Pose, Turtles, encode, encoding_for


class Sample:
    """What the hub reads of a zenoh.Sample."""

    def __init__(self, key: str, message: Any = None, payload: bytes | None = None, encoding: str = ""):
        self.key_expr = key
        self.encoding = encoding_for(type(message)) if message is not None else encoding
        self.payload = self
        self._bytes = encode(message) if message is not None else payload or b""

    def to_bytes(self) -> bytes:
        return self._bytes


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def hub() -> tuple[Hub, Clock, list[int]]:
    clock, woken = Clock(), []
    return Hub(None, lambda: woken.append(1), clock), clock, woken  # type: ignore[arg-type]


def test_which_turtle_and_what() -> None:
    assert turtle_and_section("turtle2/pose", "Pose") == ("turtle2", "poses")
    assert turtle_and_section("obstacles", "LaserScan") == ("turtle1", "scans")
    assert turtle_and_section("turtle2/obstacles", "LaserScan") == ("turtle2", "scans")
    assert turtle_and_section("navigate_to/feedback", "NavigateToFeedback") == ("turtle1", "goals")
    assert turtle_and_section("turtle3/navigate_to/feedback", "NavigateToFeedback") == ("turtle3", "goals")
    assert turtle_and_section("robot/status", "TurtleStatus") == ("turtle1", "status")
    assert turtle_and_section("turtle1/robot/status", "TurtleStatus") == ("turtle1", "status")
    assert turtle_and_section("lab/x/pose", "Pose") is None
    assert turtle_and_section("mine/chatter", "String") is None


def test_a_page_gets_the_newest_pose_not_each() -> None:
    h, _clock, woken = hub()
    for x in (1.0, 2.0, 3.0):
        h.on_sample(Sample("turtle1/pose", Pose(x=x, y=1.0, theta=0.0, stamp=int(x))))
    version, changed = h.changes(0)
    assert changed["poses"]["turtle1"]["x"] == 3.0  # the newest only: a slow page never gets a backlog
    assert len(woken) == 3
    assert h.changes(version) == (version, {})  # nothing new since
    h.on_sample(Sample("turtle2/pose", Pose(x=5.0, y=5.0, theta=1.0)))
    _v, changed = h.changes(version)
    assert list(changed["poses"]) == ["turtle2"]


def test_a_killed_turtle_is_gone_from_the_page() -> None:
    h, _clock, _ = hub()
    h.on_sample(Sample("turtle2/pose", Pose(x=5.0, y=5.0, theta=1.0)))
    version, _ = h.changes(0)
    h.on_sample(Sample("turtles", Turtles(names=["turtle1"], x=[1.0], y=[1.0], theta=[0.0])))
    _v, changed = h.changes(version)
    assert changed["poses"] == {"turtle2": None}


def test_a_goal_whose_feedback_stopped_is_no_longer_drawn() -> None:
    h, clock, _ = hub()
    fb = NavigateToFeedback(
        state="driving", distance_remaining=1, heading_remaining=0, eta=1, elapsed=1, x=1, y=1, theta=0
    )
    h.on_sample(Sample("turtle2/navigate_to/feedback", fb))
    version, changed = h.changes(0)
    assert changed["goals"]["turtle2"]["state"] == "driving"
    clock.now += 2.0
    _v, changed = h.changes(version)
    assert changed["goals"] == {"turtle2": None}


def test_rates_on_the_fake_clock_and_a_payload_that_is_garbage() -> None:
    h, clock, _ = hub()
    for _ in range(11):
        h.on_sample(
            Sample(
                "obstacles",
                LaserScan(
                    angle_min=0, angle_max=1, angle_increment=1, range_min=0, range_max=5, ranges=[1.0, float("inf")]
                ),
            )
        )
        clock.now += 0.2
    h.on_sample(Sample("turtle1/pose", payload=b"\xffnot msgpack", encoding=encoding_for(Pose)))
    rates = h.rates()
    assert abs(rates["obstacles"][0] - 5.0) < 0.01 and rates["obstacles"][1] == "turtlectl/LaserScan"
    assert h.skipped == 1  # counted and logged by no one: the page keeps the last good pose
    _v, changed = h.changes(0)
    assert changed["scans"]["turtle1"]["ranges"] == [1.0, float("inf")]
    assert "poses" not in changed
    clock.now += 10.0
    assert h.rates() == {}


def test_logs_and_watched_topics() -> None:
    h, _clock, _ = hub()
    h.on_sample(Sample("turtlectl/log/sim", Log(level=20, node="sim", message="ready")))
    h.on_sample(Sample("robot/status", payload=b"", encoding=""))  # not watched, not drawn: counted only
    version, records = h.logs(0)
    assert [r["message"] for r in records] == ["ready"]
    assert h.logs(version) == (version, [])  # asked again from there: none twice
    h.watch({"turtle1/pose"}, set())
    h.on_sample(Sample("turtle1/pose", Pose(x=1.0, y=2.0, theta=0.0)))
    version, echoes = h.echoes({"turtle1/pose"}, 0)
    assert echoes[-1]["type"] == "turtlectl/Pose" and echoes[-1]["message"]["y"] == 2.0
    assert h.echoes({"turtle1/pose"}, version) == (version, [])
    h.watch(set(), {"turtle1/pose"})
    assert h.echoes({"turtle1/pose"}, 0) == (0, [])


def test_records_held_before_come_first_and_once() -> None:
    h, _clock, _ = hub()
    live = Log(level=20, node="sim", message="live", seq=5, stamp=50)
    h.on_sample(Sample("turtlectl/log/sim", live))
    h.history([Log(level=20, node="sim", message="old", seq=1, stamp=10), live])
    assert [r["message"] for r in h.logs(0)[1]] == ["old", "live"]


def test_with_no_page_open_poses_are_counted_not_kept() -> None:
    h, _clock, _ = hub()
    h.viewed = False
    h.on_sample(Sample("turtle1/pose", Pose(x=1.0, y=1.0, theta=0.0)))
    h.on_sample(Sample("turtlectl/log/sim", Log(level=20, node="sim", message="kept")))
    version, changed = h.changes(0)
    assert changed == {} and "turtle1/pose" in h.rates()
    assert [r["message"] for r in h.logs(0)[1]] == ["kept"]
    h.viewed = True
    h.on_sample(Sample("turtle1/pose", Pose(x=2.0, y=1.0, theta=0.0)))
    assert h.changes(version)[1]["poses"]["turtle1"]["x"] == 2.0


def test_a_goal_runs_while_its_feedback_comes() -> None:
    h, clock, _ = hub()
    assert not h.goal_running("turtle1")
    fb = NavigateToFeedback(
        state="driving", distance_remaining=1, heading_remaining=0, eta=1, elapsed=1, x=1, y=1, theta=0
    )
    h.on_sample(Sample("navigate_to/feedback", fb))
    assert h.goal_running("turtle1") and not h.goal_running("turtle2")
    clock.now += 2.0
    assert not h.goal_running("turtle1")
