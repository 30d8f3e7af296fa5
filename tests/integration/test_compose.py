"""Launch composition: examples/compose/launch.toml includes one turtle's launch file
twice (turtle1's nodes, then turtle2's in its namespace), handing it an argument of its own
(``--arg speed_limit=...`` -> ``max_speed = "$(arg speed_limit)"``) and remapping the navigator's
``turtle1/cmd_vel`` to ``safety/cmd_vel``, where a node class of the example (speed_limit.py)
takes the commands and passes them on slower.  The remapped key carries the navigator's
commands, the tools see it under its new key, and the turtle keeps to the argument's limit."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from tests.integration.harness import running_system
from turtlectl.messages import Pose, Twist, decode
from turtlectl.runtime.client.api import Client

pytestmark = pytest.mark.integration

COMPOSE = Path(__file__).resolve().parents[2] / "examples" / "compose" / "launch.toml"
KINDS = ("navigator", "speed_limit", "status_monitor", "obstacle_detector")
NODES = ("sim", *KINDS, *(f"turtle2/{k}" for k in KINDS))
LIMIT = 0.4  # m/s: given on the command line, handed to each include's max_speed


def test_an_included_turtle_with_an_argument_and_a_remapped_key_drives_through_it():
    with running_system(COMPOSE, ready=NODES, extra_args=("--arg", f"speed_limit={LIMIT}")) as system:
        listed = system.run_cli("list")
        assert listed.returncode == 0, listed.stderr
        rows = {line.split()[0]: line for line in listed.stdout.splitlines() if line.startswith("  turtle2/")}
        assert "pub: turtle2/navigator " in rows["turtle2/safety/cmd_vel"], rows  # the remapped key, as list says
        assert "sub: turtle2/speed_limit" in rows["turtle2/safety/cmd_vel"], rows
        assert "pub: turtle2/speed_limit " in rows["turtle2/cmd_vel"], rows  # the navigator's remapped away
        limit = system.run_cli("param", "get", "turtle2/speed_limit", "max_speed")
        assert limit.stdout.strip() == str(LIMIT), limit.stdout + limit.stderr  # --arg -> include args -> params

        commands: list[float] = []  # the navigator's, on its remapped key
        speeds: list[float] = []  # turtle2's, as the simulator moves it
        assert system.session is not None
        subs = [
            system.session.declare_subscriber(
                "turtle2/safety/cmd_vel", lambda s: commands.append(decode(s.payload.to_bytes(), Twist).linear)
            ),
            system.session.declare_subscriber(
                "turtle2/pose", lambda s: speeds.append(decode(s.payload.to_bytes(), Pose).linear_velocity)
            ),
        ]
        try:
            with Client(system.endpoint, turtle="turtle2") as client:
                done = client.goto(4.0, 7.0, 90.0, timeout=60.0)
        finally:
            for sub in subs:
                sub.undeclare()
        assert done.success, done
        assert commands and max(commands) > LIMIT, max(commands, default=None)  # asked for more than allowed
        assert max(speeds) <= LIMIT + 1e-9 and max(speeds) > LIMIT / 2, max(speeds)  # and kept to the limit
        where = system.collect("turtle2/pose", Pose, 1, timeout=5.0)[0][1]
        assert math.dist((where.x, where.y), (4.0, 7.0)) < 0.02, where
