"""``turtlectl web`` in a real browser (Debian's Chromium, tests/integration/browser.py) against a
launched system: the page draws the turtle where its pose says, a drag on the map sends a goal, a
held arrow key drives and releasing it stops, the parameters panel sets a value and shows a
refusal, a user's node and its own type show in the panels, a viewer's page cannot drive, and the
page survives the system going away and coming back.

The page's state is read from ``window.turtlectl.model`` (and a pixel of its map); the system's from
its own messages.  Every wait is a condition under a deadline.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest
from websockets.exceptions import InvalidStatus
from websockets.sync.client import connect as ws_connect

from tests.integration.browser import browser_page, page_errors, wait_for
from tests.integration.harness import ROOT, System, credentials_at, free_port, running_system, turtlectl
from turtlectl.messages import Pose, Turtles
from turtlectl.messages.keys import POSE

pytestmark = pytest.mark.integration

#: the simulator's own stop for a silent cmd_vel, far beyond the page's (0.5 s): a turtle stopped in
#: time was stopped by the page or its server, not by the simulator
CMD_TIMEOUT = 5.0


@pytest.fixture(scope="module")
def system() -> Iterator[tuple[System, int]]:
    port = free_port()
    args = ("--web", str(port), "--set", f"sim.cmd_timeout={CMD_TIMEOUT}")
    with running_system(extra_args=args, ready=("sim", "navigator", "status_monitor", "obstacle_detector", "web")) as s:
        yield s, port


@pytest.fixture
def page(system: tuple[System, int]) -> Iterator[object]:
    s, port = system
    s.teleport(5.5, 5.5, 0.0)
    with browser_page(f"http://127.0.0.1:{port}/") as page:
        wait_for(page, "window.turtlectl && turtlectl.model.conn === 'open' && turtlectl.model.poses.turtle1", 15)
        yield page
        assert page_errors(page) == []


def pixel(page, x: float, y: float) -> tuple[int, int, int]:  # type: ignore[no-untyped-def]
    """The colour the map drew at world point (x, y) m."""
    return tuple(
        page.evaluate(
            f"""(() => {{ const w = turtlectl.world, [sx, sy] = w.toScreen({x}, {y}), d = window.devicePixelRatio || 1;
            return Array.from(w.ctx.getImageData(Math.round(sx * d), Math.round(sy * d), 1, 1).data.slice(0, 3)); }})()"""
        )
    )


def test_the_page_draws_the_turtle_where_its_pose_says(system, page) -> None:  # type: ignore[no-untyped-def]
    s, _port = system
    s.teleport(3.0, 7.0, 0.0)
    truth = s.wait_stopped()
    drawn = wait_for(page, f"(p => p && Math.abs(p.x - {truth.x}) < 0.01 && p)(turtlectl.model.poses.turtle1)")
    assert math.hypot(drawn["x"] - truth.x, drawn["y"] - truth.y) < 0.01
    wait_for(page, "turtlectl.model.stats.drawn > 0 && turtlectl.model.poses.turtle1.drawn")
    r, g, b = pixel(page, truth.x, truth.y)
    assert r > 200 and g > 150 and b < 150, (r, g, b)  # the turtle (turtle1's yellow) is drawn on its pose ...
    r, g, b = pixel(page, truth.x + 1.5, truth.y - 1.5)
    assert b > 200 and r < 120, (r, g, b)  # ... and not a metre and a half away: the world's blue
    assert page.evaluate("turtlectl.model.stats.latencies.length") > 0


def test_a_click_sends_nothing_and_the_map_stays_put(system, page) -> None:  # type: ignore[no-untyped-def]
    s, _port = system
    box = page.locator("#map").bounding_box()
    page.mouse.click(*page.evaluate("turtlectl.world.pagePoint(2, 2)"))  # the map's focus, no goal
    wait_for(page, "document.getElementById('said').textContent.startsWith('drag to send a goal')")
    rest = s.collect(POSE, Pose, 30, timeout=5.0)
    assert all(abs(p.linear_velocity) < 1e-6 and abs(p.angular_velocity) < 1e-6 for _t, p in rest)
    assert page.evaluate("document.activeElement.id") == "map"
    page.evaluate("turtlectl.say('a long line '.repeat(60), 'bad')")  # what a long refusal would say
    assert page.locator("#map").bounding_box() == box  # the map did not move under the pointer


def test_a_canceled_goal_says_so_once(system, page) -> None:  # type: ignore[no-untyped-def]
    s, _port = system
    s.teleport(1.5, 5.5, 0.0)
    drag(page, (9.5, 5.5), (10.5, 5.5))
    wait_for(page, "turtlectl.model.goals.turtle1", 10)
    page.click("#cancel")
    outcome = wait_for(page, "turtlectl.model.outcomes.turtle1", 10)
    assert not outcome["success"] and outcome["reason"] == "canceled"
    line = page.inner_text("#goal")
    assert line.startswith("turtle1: not reached (canceled)") and line.count("canceled") <= 3, line
    s.wait_stopped()


def test_a_drag_on_the_map_sends_a_goal_and_the_turtle_arrives(system, page) -> None:  # type: ignore[no-untyped-def]
    s, _port = system
    start = page.evaluate("turtlectl.world.pagePoint(8, 3)")
    heading = page.evaluate("turtlectl.world.pagePoint(8, 4)")  # dragged north: theta 90 degrees
    page.mouse.move(*start)
    page.mouse.down()
    page.mouse.move(*heading, steps=5)
    page.mouse.up()
    outcome = wait_for(page, "turtlectl.model.outcomes.turtle1", 30)
    assert outcome["success"], outcome
    assert outcome["time_taken"] > 0
    end = s.wait_stopped()
    assert math.hypot(end.x - 8.0, end.y - 3.0) < 0.05
    assert abs(math.degrees(end.theta) - 90.0) < 2.0
    assert "reached in" in page.inner_text("#goal")


def test_a_held_arrow_key_drives_and_releasing_it_stops(system, page) -> None:  # type: ignore[no-untyped-def]
    s, _port = system
    s.teleport(2.0, 5.5, 0.0)
    page.focus("#map")
    page.keyboard.down("ArrowUp")
    moving = s.wait_moving(speed=1.0, timeout=5.0)
    assert moving.linear_velocity > 1.0
    wait_for(page, "turtlectl.model.poses.turtle1.x > 3", 5)
    page.keyboard.up("ArrowUp")
    s.wait_stopped(timeout=CMD_TIMEOUT - 2.0)  # the key's stop, long before the simulator's own
    rest = s.latest_pose()
    assert rest.x > 3.0 and abs(rest.linear_velocity) < 1e-6


def test_the_pad_drives_and_losing_focus_stops_the_keys(system, page) -> None:  # type: ignore[no-untyped-def]
    s, _port = system
    s.teleport(2.0, 5.5, 0.0)
    page.click("#map", button="right")  # the map had focus (the keys' place) before the pad is pressed
    box = page.locator("#pad [data-drive=fwd]").bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    s.wait_moving(speed=1.0, timeout=5.0)  # the pad drives, held, and stops when released
    page.mouse.up()
    s.wait_stopped(timeout=CMD_TIMEOUT - 2.0)
    page.focus("#map")
    page.keyboard.down("ArrowLeft")  # turning in place
    wait_for(page, "Math.abs(turtlectl.model.poses.turtle1.w) > 1", 5)
    page.focus("#turtle")  # the map loses focus with the key still held
    wait_for(page, "turtlectl.model.poses.turtle1.w === 0", CMD_TIMEOUT - 2.0)
    page.keyboard.up("ArrowLeft")


def test_a_page_that_stops_sending_stops_the_turtle(system, page) -> None:  # type: ignore[no-untyped-def]
    """The server's deadman: one drive command and nothing after (a page frozen, a network lost)."""
    s, _port = system
    s.teleport(2.0, 5.5, 0.0)
    page.evaluate("turtlectl.send({t: 'drive', turtle: 'turtle1', linear: 1.5, angular: 0})")
    s.wait_moving(speed=0.5, timeout=5.0)
    s.wait_stopped(timeout=CMD_TIMEOUT - 2.0)


def drag(page, start: tuple[float, float], end: tuple[float, float], modifier: str = "") -> None:  # type: ignore[no-untyped-def]
    """Press at world point ``start`` (m) and release at ``end``, holding ``modifier`` (Shift, Alt)."""
    if modifier:
        page.keyboard.down(modifier)
    page.mouse.move(*page.evaluate(f"turtlectl.world.pagePoint({start[0]}, {start[1]})"))
    page.mouse.down()
    page.mouse.move(*page.evaluate(f"turtlectl.world.pagePoint({end[0]}, {end[1]})"), steps=4)
    page.mouse.up()
    if modifier:
        page.keyboard.up(modifier)


def test_spawn_teleport_and_kill_by_gestures(system, page) -> None:  # type: ignore[no-untyped-def]
    """alt+drag spawns, shift+drag teleports, kill removes; a goal for a turtle no navigator drives says why."""
    s, _port = system
    drag(page, (2.0, 9.5), (2.0, 10.5), "Alt")  # dragged north: facing 90 degrees
    said = wait_for(page, "(t => t.startsWith('spawned') && t)(document.getElementById('said').textContent)", 10)
    name = said.split()[1].rstrip(":")
    assert page.evaluate("turtlectl.model.turtle") == name  # the new turtle is the chosen one, and it says so
    assert "chosen now" in said
    born = s.collect(f"{name}/pose", Pose, 1, timeout=5.0)[-1][1]
    assert math.hypot(born.x - 2.0, born.y - 9.5) < 0.05 and abs(math.degrees(born.theta) - 90.0) < 1.0
    drag(page, (9.0, 9.5), (10.0, 9.5))  # a goal: but only turtle1 has a navigator here
    wait_for(page, f"document.getElementById('said').textContent.includes('{name} has no navigator')")
    drag(page, (6.0, 9.5), (6.0, 8.5), "Shift")  # teleported there, facing south
    wait_for(page, f"(p => p && Math.abs(p.x - 6) < 0.05)(turtlectl.model.poses['{name}'])", 10)
    moved = s.collect(f"{name}/pose", Pose, 1, timeout=5.0)[-1][1]
    assert math.hypot(moved.x - 6.0, moved.y - 9.5) < 0.05 and abs(abs(math.degrees(moved.theta)) - 90.0) < 1.0
    assert page.evaluate(f"turtlectl.model.trails['{name}'].includes(null)")  # no trail drawn across the jump
    page.click("#kill")
    wait_for(page, f"!turtlectl.model.poses['{name}']", 10)
    # the list no longer offers it, and turtle1 is the chosen one again
    wait_for(
        page,
        f"turtlectl.model.turtle === 'turtle1' && ![...document.querySelectorAll('#turtle option')].some(o => o.value === '{name}')",
        5,
    )
    assert name not in s.collect("turtles", Turtles, 1, timeout=5.0)[-1][1].names  # the simulator's own list


def test_the_parameters_panel_sets_a_value_and_shows_a_refusal(system, page) -> None:  # type: ignore[no-untyped-def]
    s, _port = system
    page.click("#tabs button[data-tab=params]")
    wait_for(page, "[...document.querySelectorAll('#param-node option')].some(o => o.value === 'navigator')")
    page.select_option("#param-node", "navigator")
    field = "#params input[data-param=goal_timeout]"
    page.wait_for_selector(field)
    page.fill(field, "45")
    page.press(field, "Enter")
    said = wait_for(page, "(e => e.className === 'good' && e.textContent)(document.getElementById('param-said'))")
    assert "goal_timeout = 45.0" in said
    assert param(s, "navigator", "goal_timeout") == 45.0
    page.fill(field, "-3")
    page.press(field, "Enter")
    refused = wait_for(page, "(e => e.className === 'bad' && e.textContent)(document.getElementById('param-said'))")
    assert refused == "navigator: goal_timeout must be >= 0.1 (got -3)"  # the node's words, as param set says them
    assert param(s, "navigator", "goal_timeout") == 45.0


def param(s: System, node: str, name: str) -> object:
    got = s.run_cli("param", "get", node, name, "--connect", s.endpoint)
    assert got.returncode == 0, got.stderr
    return json.loads(got.stdout.split()[-1])


def test_another_origin_is_refused_and_a_bad_frame_is_answered(system) -> None:  # type: ignore[no-untyped-def]
    _s, port = system
    with pytest.raises(InvalidStatus) as refused:
        ws_connect(f"ws://127.0.0.1:{port}/ws", origin="http://evil.example", open_timeout=5).close()
    assert refused.value.response.status_code == 403
    with ws_connect(f"ws://127.0.0.1:{port}/ws", open_timeout=5) as ws:
        assert json.loads(ws.recv(timeout=5))["t"] == "hello"
        ws.send('{"t": "fly"}')
        while (frame := json.loads(ws.recv(timeout=5)))["t"] != "error":
            pass
        assert "unknown frame kind" in frame["text"]
        ws.send(json.dumps({"t": "watch", "keys": ["robot/status"]}))  # still open, still answering
        while (frame := json.loads(ws.recv(timeout=5)))["t"] != "echo":
            pass
        assert frame["key"] == "robot/status" and frame["type"] == "turtlectl/TurtleStatus"


def test_a_users_nodes_and_own_type_show_in_the_panels(tmp_path: Path) -> None:
    """The capstone as the lesson builds it (its own nodes, its own TurtleStatus), with ``run = "web"``."""
    project = tmp_path / "capstone"
    shutil.copytree(ROOT / "examples" / "capstone", project, ignore=shutil.ignore_patterns("tests", "__pycache__"))
    port = free_port()
    launch = project / "launch.toml"
    launch.write_text(launch.read_text() + f'\n[[node]]\nname = "web"\nrun = "web"\nparams = {{ port = {port} }}\n')
    ready = ("sim", "navigator", "obstacle_detector", "web")  # status_monitor's status is its own type
    with running_system(launch, ready=ready, cwd=project), browser_page(f"http://127.0.0.1:{port}/") as page:
        wait_for(page, "turtlectl.model.graph.nodes.some(n => n.name === 'status_monitor' && n.kind !== '?')", 15)
        kinds = {n["name"]: n["kind"] for n in page.evaluate("turtlectl.model.graph.nodes")}
        assert "status_monitor.py:StatusMonitor" in kinds["status_monitor"]
        page.click("#tabs button[data-tab=topics]")
        row = wait_for(page, "turtlectl.model.graph.topics.find(t => t.key === 'robot/status' && t.rate > 5)", 15)
        assert row["type"] == "capstone_msgs/TurtleStatus"
        assert "capstone_msgs/TurtleStatus" in page.inner_text("#topics tr[data-key='robot/status']")
        page.click("#topics tr[data-key='robot/status'] td")
        echo = wait_for(page, "(t => t.includes('battery') && t)(document.getElementById('echo').textContent)", 10)
        assert echo.startswith("capstone_msgs/TurtleStatus")
        assert page_errors(page) == []


@pytest.fixture
def credentials_file(tmp_path: Path) -> Iterator[Path]:
    """The credentials file of this test's secure system (never the user's own)."""
    with credentials_at(tmp_path / "credentials.json") as path:
        yield path


def serve(endpoint: str, port: int, *more: str) -> subprocess.Popen[str]:
    """``turtlectl web`` in a process group of its own, its output kept for a failure's message."""
    return subprocess.Popen(
        [*turtlectl(), "web", "--port", str(port), "--connect", endpoint, *more],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )


def stop(server: subprocess.Popen[str]) -> None:
    if server.poll() is None:
        os.killpg(server.pid, signal.SIGKILL)
    server.wait(10)


def test_a_viewers_page_cannot_drive(credentials_file: Path) -> None:
    port = free_port()
    with running_system(extra_args=("--secure",)) as s:
        server = serve(s.endpoint, port, "--role", "viewer")
        try:
            with browser_page(f"http://127.0.0.1:{port}/") as page:
                wait_for(page, "turtlectl.model.hello && turtlectl.model.poses.turtle1", 20)
                assert page.evaluate("turtlectl.model.hello.role") == "viewer"
                assert page.evaluate("[...document.querySelectorAll('#pad button')].every(b => b.disabled)")
                before = s.latest_pose()
                page.evaluate("turtlectl.send({t: 'drive', turtle: 'turtle1', linear: 2, angular: 0})")
                wait_for(page, "turtlectl.model.errors.some(e => e.includes('viewer role cannot drive'))")
                reply = page.evaluate("turtlectl.request({t: 'goal', turtle: 'turtle1', x: 2, y: 2, theta: 0})")
                assert reply["ok"] is False and "viewer role cannot send goals" in reply["text"]
                drag(page, (3.0, 3.0), (4.0, 3.0))  # a goal's gesture says which role may
                wait_for(page, "document.getElementById('said').textContent.includes('(viewer) can only watch')")
                page.focus("#map")
                page.keyboard.down("ArrowUp")  # the keys say why, and send nothing
                wait_for(page, "document.getElementById('said').textContent.includes('cannot drive')")
                page.keyboard.up("ArrowUp")
                after = s.collect(POSE, Pose, 20, timeout=5.0)[-1][1]
                assert math.hypot(after.x - before.x, after.y - before.y) < 1e-6
                assert [e for e in page_errors(page) if "cannot drive" not in e] == []
        finally:
            stop(server)


def test_the_page_survives_the_system_restarting() -> None:
    port = free_port()
    first = System()
    try:
        first.wait_ready()
        router = first.port
        server = serve(first.endpoint, port)
        try:
            with browser_page(f"http://127.0.0.1:{port}/") as page:
                wait_for(page, "turtlectl.model.poses.turtle1", 20)
                first.stop()
                wait_for(page, "turtlectl.model.router === 'lost'", 15)
                assert "lost" in page.inner_text("#banner")
                page.evaluate("delete turtlectl.model.poses.turtle1")
                second = System(port=router)
                try:
                    second.wait_ready()
                    wait_for(page, "turtlectl.model.router === 'ok' && turtlectl.model.poses.turtle1", 20)
                    assert "back" in page.inner_text("#banner")
                finally:
                    second.kill_everything()
                assert page_errors(page) == []
        finally:
            stop(server)
    finally:
        first.kill_everything()


def test_a_page_of_a_launch_reconnects_when_the_launch_is_back() -> None:
    """``run = "web"`` (here ``launch --web``): the page's own server goes with the system, and the
    page connects again when it is back."""
    port = free_port()
    first = System(extra_args=("--web", str(port)))
    try:
        first.wait_ready(("sim", "web"))
        router = first.port
        with browser_page(f"http://127.0.0.1:{port}/") as page:
            wait_for(page, "turtlectl.model.poses.turtle1", 20)
            first.stop()
            wait_for(page, "turtlectl.model.conn === 'reconnecting'", 15)
            assert "reconnecting" in page.inner_text("#banner")
            second = System(extra_args=("--web", str(port)), port=router)
            try:
                second.wait_ready(("sim", "web"))
                wait_for(page, "turtlectl.model.conn === 'open' && turtlectl.model.stats.reconnects >= 1", 20)
                wait_for(page, "document.getElementById('banner').textContent.includes('reconnected')", 5)
            finally:
                second.kill_everything()
            # the failed attempts while the server was down are the browser's own console lines
            assert [e for e in page_errors(page) if "WebSocket" not in e and "ERR_CONNECTION_REFUSED" not in e] == []
    finally:
        first.kill_everything()
