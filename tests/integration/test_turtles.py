"""Several turtles in one world, as turtlesim's spawn and kill make
them: each turtle's keys under its name, refusals with their reasons, turtles solid to each
other and seen by turtle1's scan, reset as turtlesim's (the others removed)."""

from __future__ import annotations

import math
import os
import signal
import time

import pyte
import pytest

from tests.integration.harness import pump, running_system, set_winsize, view_in_pty
from turtlectl.messages import LaserScan, Pose, Turtles, Twist, encode, encoding_for
from turtlectl.messages.keys import OBSTACLES, TURTLES

pytestmark = pytest.mark.integration

SPAWN = (5.544445, 5.544445)  # turtle1's, from launch.toml


@pytest.fixture(scope="module")
def system():
    with running_system() as s:
        yield s


def turtles(system) -> dict[str, tuple[float, float]]:
    msg = system.collect(TURTLES, Turtles, 1, timeout=5.0)[0][1]
    return {n: (x, y) for n, x, y in zip(msg.names, msg.x, msg.y, strict=True)}


def test_spawn_names_a_turtle_whose_keys_are_under_its_name_and_kill_removes_it(system):
    done = system.run_cli("spawn", "2", "2", "90")
    assert done.returncode == 0 and done.stdout.strip() == "turtle2", done.stdout + done.stderr
    pose = system.collect("turtle2/pose", Pose, 1, timeout=5.0)[0][1]
    assert (pose.x, pose.y) == (2.0, 2.0) and pose.theta == pytest.approx(math.pi / 2)
    assert set(turtles(system)) == {"turtle1", "turtle2"}
    moved = system.run_cli("teleport", "3", "2", "0", "--turtle", "turtle2")
    assert moved.returncode == 0, moved.stderr
    assert system.collect("turtle2/pose", Pose, 1, timeout=5.0)[0][1].x == 3.0
    assert system.run_cli("spawn", "4", "2", "0", "--name", "alice").stdout.strip() == "alice"
    killed = system.run_cli("kill", "alice")
    assert killed.returncode == 0 and killed.stdout.strip() == "killed alice", killed.stderr
    assert set(turtles(system)) == {"turtle1", "turtle2"}
    listed = system.run_cli("list").stdout
    assert "turtle2/pose" in listed and "alice/pose" not in listed, listed
    system.run_cli("kill", "turtle2")


@pytest.mark.parametrize(
    ("argv", "reason"),
    [
        (("spawn", "2", "9", "0"), "cannot spawn: (2, 9) is inside an obstacle"),
        (("spawn", "12", "2", "0"), "cannot spawn: (12, 2) is outside the world"),
        (("spawn", "5.7", "5.5", "0"), "nearer than two turtle radii (0.6 m)"),
        (("spawn", "2", "2", "0", "--name", "turtle1"), "cannot spawn: a turtle named turtle1 exists"),
        (("spawn", "2", "2", "0", "--name", "a/b"), "is not a turtle name"),
        (("kill", "bob"), "no turtle named 'bob' (turtles: turtle1)"),
    ],
)
def test_a_refusal_says_why_exit_2(system, argv, reason):
    done = system.run_cli(*argv)
    assert done.returncode == 2 and reason in done.stderr, done.stdout + done.stderr


def test_turtles_are_solid_to_each_other_and_turtle1s_scan_sees_the_other(system):
    assert system.run_cli("spawn", "8", str(SPAWN[1]), "180", "--name", "bob").returncode == 0
    twist = encode(Twist(linear=2.0))
    contact: list[Pose] = []

    def pushed() -> bool:  # drive bob at turtle1 until it stops on contact
        system.session.put("bob/cmd_vel", twist, encoding=encoding_for(Twist))
        pose = system.collect("bob/pose", Pose, 1, timeout=5.0)[0][1]
        if pose.contact:
            contact.append(pose)
        return bool(contact)

    system.wait_until(pushed, 10.0, "bob in contact with turtle1")
    system.wait_line(r"sim .*bob: contact with another turtle at \(6\.144, 5\.544\): stopped", 5.0)
    gap = math.hypot(contact[0].x - SPAWN[0], contact[0].y - SPAWN[1])
    assert gap == pytest.approx(0.6, abs=1e-6)  # two turtle radii, never nearer
    scan = system.collect(OBSTACLES, LaserScan, 2, timeout=5.0)[-1][1]
    ahead = scan.ranges[len(scan.ranges) // 2]  # beam 0 rad: turtle1 faces bob (+x)
    assert ahead == pytest.approx(gap - 0.3, abs=0.02), scan.ranges  # bob's near side
    done = system.run_cli("reset")
    assert done.returncode == 0, done.stderr
    assert set(turtles(system)) == {"turtle1"}  # turtlesim's reset: the others removed


def test_view_draws_a_spawned_turtle_and_names_it(system):
    assert system.run_cli("spawn", "3", "8", "90", "--name", "carol").returncode == 0
    pid, fd = view_in_pty(system.endpoint)
    screen = pyte.Screen(120, 30)
    stream = pyte.ByteStream(screen)
    try:
        set_winsize(fd, 30, 120)
        os.kill(pid, signal.SIGWINCH)
        deadline = time.monotonic() + 15
        while "also: carol (3.0, 8.0)" not in "\n".join(screen.display):
            assert time.monotonic() < deadline, "\n".join(screen.display)
            assert pump(fd, stream, 0.2)
        assert "↑" in "\n".join(screen.display[1:-4])  # carol faces +y
    finally:
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        os.close(fd)
        system.run_cli("kill", "carol")
