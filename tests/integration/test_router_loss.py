"""One behaviour on a lost router for every long-running tool, against a real router killed
and started again: echo, hz and log -f say once that the router is lost, keep waiting, say
once that it is back and go on; ``--exit-on-loss`` makes them exit 3 instead.  ``record``
marks the gap in its file and ``info`` lists it."""

from __future__ import annotations

import json
import signal
import subprocess
import time

import pytest

from tests.integration.harness import Router, running_system, turtlectl
from tests.integration.test_quiet_streams import Watched
from turtlectl.messages import TurtleStatus

pytestmark = pytest.mark.integration


@pytest.fixture()
def router():
    r = Router()
    r.start()
    yield r
    r.kill()


COMMANDS = {
    "echo": ("echo", "robot/status", "--field", "battery"),
    "hz": ("hz", "robot/status"),
    "log": ("log", "-f"),
}


def test_long_running_tools_wait_for_a_lost_router_and_say_when_it_is_back(router):
    with running_system(join=router.endpoint) as system:
        tools = {name: Watched(router.endpoint, *argv) for name, argv in COMMANDS.items()}
        try:
            for name in ("echo", "hz"):
                Watched.next_line(tools[name].out, 15.0)  # receiving
            router.kill()
            for name, tool in tools.items():
                _, line = Watched.next_line(tool.err, 10.0, "lost the router")
                assert line.startswith(f"lost the router at {router.endpoint}: waiting for it to come back"), (
                    name,
                    line,
                )
                assert tool.proc.poll() is None, f"{name} exited on a lost router"
            system.wait_line(r"navigator .*lost the router", 10.0)
            router.start()
            for name, tool in tools.items():
                _, line = Watched.next_line(tool.err, 20.0, "is back")
                assert line.startswith(f"the router at {router.endpoint} is back after "), (name, line)
            for name in ("echo", "hz"):
                tools[name].drained(tools[name].out)
                Watched.next_line(tools[name].out, 15.0)  # receiving again
            for name, tool in tools.items():
                said = [text for _, text in tool.drained(tool.err) if "router" in text]
                assert not said, f"{name} said more about the router: {said}"
                tool.proc.send_signal(signal.SIGINT)
                assert tool.finish(10) == 0, name
        finally:
            for tool in tools.values():
                tool.kill()


def test_exit_on_loss_ends_every_long_running_tool_with_code_3(router):
    with running_system(join=router.endpoint):
        tools = {name: Watched(router.endpoint, *argv, "--exit-on-loss") for name, argv in COMMANDS.items()}
        try:
            for name in ("echo", "hz"):
                Watched.next_line(tools[name].out, 15.0)
            router.kill()
            lost = time.monotonic()
            for name, tool in tools.items():
                assert tool.finish(10) == 3, name
                assert time.monotonic() - lost < 5.0
                errors = [text for _, text in tool.drained(tool.err)]
                assert errors[-1].startswith(f"turtlectl: error: lost the router at {router.endpoint}: no more "), (
                    name,
                    errors,
                )
        finally:
            for tool in tools.values():
                tool.kill()


def test_record_marks_the_gap_and_info_lists_it_play_reads_past_it(router, tmp_path):
    path = tmp_path / "gap.mcap"
    with running_system(join=router.endpoint) as system:
        recorder = Watched(router.endpoint, "record", "robot/status", "-o", str(path))
        try:
            Watched.next_line(recorder.err, 15.0, "recording robot/status")
            system.collect("robot/status", TurtleStatus, 5, 10.0)
            router.kill()
            Watched.next_line(recorder.err, 10.0, "lost the router")
            system.wait_line(r"status_monitor .*lost the router", 10.0)
            router.start()
            Watched.next_line(recorder.err, 20.0, "is back")
            system.wait_line(r"status_monitor .*router at .* is reached", 15.0)
            system.collect("robot/status", TurtleStatus, 5, 10.0)
            recorder.proc.send_signal(signal.SIGINT)
            assert recorder.finish(15) == 0
        finally:
            recorder.kill()
    info = subprocess.run([*turtlectl(), "info", str(path), "--json"], capture_output=True, text=True, timeout=30)
    assert info.returncode == 0, info.stderr
    gaps = json.loads(info.stdout)["gaps"]
    assert len(gaps) == 1, gaps
    assert 0.5 < gaps[0]["duration"] < 30, gaps
    text = subprocess.run([*turtlectl(), "info", str(path)], capture_output=True, text=True, timeout=30)
    assert "router lost" in text.stdout, text.stdout
    played = subprocess.run(
        [*turtlectl(), "play", str(path), "--rate", "20", "--connect", router.endpoint],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert played.returncode == 0, played.stderr


def _map_cells(screen, char: str) -> int:
    return sum(row.count(char) for row in screen.display[1:] if row.startswith("|"))


def test_a_view_started_before_the_system_draws_its_world_when_it_appears(router):
    import os

    import pyte

    from tests.integration.harness import in_pty, pump, set_winsize

    pid, fd = in_pty("view", "--connect", router.endpoint)
    screen = pyte.Screen(100, 30)
    stream = pyte.ByteStream(screen)
    try:
        set_winsize(fd, 30, 100)
        os.kill(pid, signal.SIGWINCH)
        deadline = time.monotonic() + 15
        while "waiting for turtle1/pose" not in "\n".join(screen.display):
            assert time.monotonic() < deadline, "\n".join(screen.display)
            assert pump(fd, stream, 0.2)
        assert _map_cells(screen, "o") == 0  # no world yet: the default, empty one
        with running_system(join=router.endpoint):
            deadline = time.monotonic() + 10
            while _map_cells(screen, "o") < 5:  # the launch file's obstacles
                assert time.monotonic() < deadline, "\n".join(screen.display)
                assert pump(fd, stream, 0.2)
        os.kill(pid, signal.SIGINT)
        while pump(fd, stream, 0.1):
            pass
        _, status = os.waitpid(pid, 0)
        assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0
    finally:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        os.close(fd)


def test_a_supervisor_says_when_nodes_it_did_not_start_leave_and_come_back():
    def host_b(endpoint: str) -> subprocess.Popen:
        """Another supervisor joining with the node A leaves out (the harness's System would kill
        every node it sees at its end, A's included)."""
        return subprocess.Popen(
            [*turtlectl(), "launch", "--connect", endpoint, "--only", "status_monitor"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            stdin=subprocess.DEVNULL,
            start_new_session=True,
        )

    ready = ("sim", "navigator", "obstacle_detector")
    with running_system(ready=ready, extra_args=("--exclude", "status_monitor")) as a:
        b = host_b(a.endpoint)
        try:
            a.wait_until(lambda: "status_monitor" in a.alive, 20.0, "host B's status_monitor")
            pid = a.alive["status_monitor"]
            a.wait_line(rf"status_monitor runs elsewhere \(pid {pid} on .+; not started here\)", 10.0)
            b.send_signal(signal.SIGINT)
            assert b.wait(10) == 0
            a.wait_line(rf"status_monitor left \(pid {pid} on .+; not started here\)", 10.0)
            b = host_b(a.endpoint)
            a.wait_line(r"status_monitor is back \(pid \d+ on .+; not started here\)", 20.0)
        finally:
            if b.poll() is None:
                b.kill()
                b.wait(5)


def test_a_nodes_goal_whose_server_is_killed_ends_naming_it(caplog):
    import os

    import zenoh

    from tests.integration.harness import NoParams
    from turtlectl.messages import NavigateToFeedback, NavigateToRequest, NavigateToResponse
    from turtlectl.runtime.config import NodeConfig
    from turtlectl.runtime.goal_client import GoalFailed
    from turtlectl.runtime.node import Node
    from turtlectl.runtime.session import close_session, peer_config

    with running_system() as system:
        session = zenoh.open(peer_config(system.endpoint))
        try:
            node = Node(NodeConfig(name="caller", kind="test", connect=system.endpoint), NoParams(), session)
            client = node.goal_client("navigate_to", NavigateToRequest, NavigateToFeedback, NavigateToResponse)
            feedback: list[NavigateToFeedback] = []

            def run_until(done, timeout: float, what: str) -> None:
                assert node.spin_until(done, timeout), what

            # A session just opened may not have the navigator's queryable routed yet: a goal
            # sent then finds nothing serving it.  Its server's token says when it is reachable.
            run_until(lambda: client.servers, 10.0, "navigate_to's server never seen")
            future = client.send(NavigateToRequest(x=1.0, y=9.0, theta=0.0), on_feedback=feedback.append)
            run_until(lambda: feedback or future.done(), 10.0, "no feedback")
            assert not future.done(), future.exception()
            pid = system.alive["navigator"]
            with caplog.at_level("INFO"):
                os.kill(pid, signal.SIGKILL)
                run_until(future.done, 10.0, "the goal did not end")
            assert isinstance(future.exception(), GoalFailed)
            assert str(future.exception()) in (
                f"navigate_to's server navigator (pid {pid}) went away before the goal ended",
                "navigate_to ended without a result (its server stopped answering: did it exit?)",
            )
            run_until(lambda: any("went away" in r.getMessage() for r in caplog.records), 10.0, "not logged")
        finally:
            close_session(session)


def test_teleop_and_view_wait_for_a_lost_router_or_exit_3_with_exit_on_loss(router):
    """teleop stops sending while the router is lost and says so; view says so on its status
    line; both keep running, and both exit 3 with --exit-on-loss."""
    import os

    from tests.integration.harness import in_pty, pump, set_winsize
    from tests.integration.test_teleop import Screen, finish

    def started(*argv: str, shown: str) -> tuple[int, int, Screen]:
        pid, fd = in_pty(*argv, "--connect", router.endpoint)
        set_winsize(fd, 30, 200)
        screen = Screen()
        deadline = time.monotonic() + 15
        while shown not in screen.text:
            assert time.monotonic() < deadline, screen.text
            assert pump(fd, screen, 0.1), screen.text
        return pid, fd, screen

    def wait_for(fd: int, screen: Screen, text: str, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        while text not in screen.text:
            assert time.monotonic() < deadline, screen.text[-2000:]
            assert pump(fd, screen, 0.1), screen.text[-2000:]

    with running_system(join=router.endpoint):
        waiting = [started("teleop", shown="| x "), started("view", shown="battery")]
        leaving = [
            started("teleop", "--exit-on-loss", "--force", shown="| x "),  # the first drives turtle1 already
            started("view", "--exit-on-loss", shown="battery"),
        ]
        try:
            for _, _, screen in waiting + leaving:
                screen.text = ""
            router.kill()
            _, teleop_fd, teleop_screen = waiting[0]
            wait_for(teleop_fd, teleop_screen, f"lost the router at {router.endpoint}", 10.0)
            wait_for(waiting[1][1], waiting[1][2], f"no router at {router.endpoint}", 10.0)
            for pid, fd, screen in leaving:
                assert finish(pid, fd, screen) == 3, screen.text[-2000:]
            for pid, _, _ in waiting:
                assert os.waitpid(pid, os.WNOHANG) == (0, 0), "exited on a lost router"
            router.start()
            wait_for(teleop_fd, teleop_screen, f"the router at {router.endpoint} is back", 20.0)
            for _, fd, _ in waiting:
                os.write(fd, b"q")
            for pid, fd, screen in waiting:
                assert finish(pid, fd, screen) == 0
        finally:
            for pid, fd, _ in waiting + leaving:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                try:
                    os.close(fd)
                except OSError:
                    pass
