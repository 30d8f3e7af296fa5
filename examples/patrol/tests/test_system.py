"""The project's nodes in the real system, through turtlectl's pytest plugin: the
``turtlectl_system`` fixture launches ``launch.toml`` (pytest.ini) on a free port, waits until
every node is ready and hands over a ``turtlectl.Client``.  With ``turtlectl_scope = module``
(pytest.ini) the tests below share one system, in this order: it is stopped after the last."""

from __future__ import annotations

import math
import time

import pytest

from turtlectl.messages import Pose


def poses_until(client, done, seconds: float) -> Pose:
    """Poses of the turtle until ``done(pose)``; fails after ``seconds`` s of driving."""
    deadline = time.monotonic() + seconds
    sub = client.subscribe("turtle1/pose")
    try:
        while time.monotonic() < deadline:
            pose = sub.next(timeout=5.0)
            if done(pose):
                return pose
    finally:
        sub.undeclare()
    pytest.fail(f"not within {seconds:g} s")


def test_the_patrol_runs_beside_turtlectl_s_nodes_with_its_parameters(turtlectl_system):
    client = turtlectl_system
    assert {n.name for n in client.nodes()} >= {"sim", "navigator", "patrol"}
    assert client.param("patrol", "side") == 3.0


def test_the_patrol_drives_to_its_first_corner(turtlectl_system):
    client = turtlectl_system  # the same system as the test above: its first lap has just begun
    # the square of side 3 m round (5.5, 5.5): its first corner is (4, 4)
    poses_until(client, lambda p: math.hypot(p.x - 4.0, p.y - 4.0) < 0.05, seconds=60.0)
