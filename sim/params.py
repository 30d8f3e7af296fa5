"""Parameters of the simulator process (set in the launch file's ``[node.params]``), and what it
declares, its ``SIM_CLAIMS`` and ``SIM_INTERFACE`` (written once here, pure: the Simulator class
carries them and nodes.kinds reads them, as nodes.params does for the other built-in nodes)."""

from __future__ import annotations

from typing import ClassVar

import msgspec

from turtlectl.messages.keys import (
    CLOCK,
    KILL,
    POSE,
    RESET,
    SPAWN,
    TURTLES,
    WORLD_KEY,
    cmd_vel_key,
    moving_key,
    pose_key,
    teleport_key,
)
from turtlectl.messages.units import Finite, ShortTimeout, TimeFactor
from turtlectl.messages.world import TURTLESIM_SIZE
from turtlectl.runtime.config import Claim, Interface


class TurtleSpawn(msgspec.Struct, frozen=True, forbid_unknown_fields=True, kw_only=True):
    """A turtle the simulator makes at start, beside turtle1 (a ``[[group]]``'s turtle):
    ``{ name = "turtle2", x = 2.0, y = 2.0, theta = 0.0 }``; ``reset`` puts it back here."""

    name: str  # -: the turtle's name: its keys are under it (turtle2/pose), as a group's namespace
    x: Finite  # m
    y: Finite  # m
    theta: Finite = 0.0  # rad


Spawns = list[TurtleSpawn]


class SimParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """The simulator: where the turtle spawns (inside the world and outside every obstacle:
    the launch file's validation checks both) and when it stops without commands
    (``# unit: meaning`` per field)."""

    x: Finite = TURTLESIM_SIZE / 2.0  # m: spawn position (turtlesim's centre by default)
    y: Finite = TURTLESIM_SIZE / 2.0  # m: spawn position
    theta: Finite = 0.0  # rad: spawn heading
    cmd_timeout: ShortTimeout = 1.0  # s: after the last cmd_vel the turtle stops (turtlesim: 1 s)
    turtles: Spawns = msgspec.field(default_factory=list)  # m, rad: more turtles at start, { name, x, y, theta }
    real_time_factor: TimeFactor = 1.0  # s/s: simulated seconds per wall second (5: five times as fast)

    FIXED: ClassVar[dict[str, str]] = {
        name: "the spawn pose is read once, at start (`turtlectl teleport` moves the turtle)"
        for name in ("x", "y", "theta")
    } | {"turtles": "the turtles are made once, at start (`turtlectl spawn` adds one)"}


SIM_CLAIMS = (Claim("pub", POSE),)
SIM_INTERFACE = Interface(
    publishes=(pose_key("*"), TURTLES, CLOCK),
    subscribes=(cmd_vel_key("*"),),
    serves=(teleport_key("*"), RESET, SPAWN, KILL, WORLD_KEY),
    calls=(moving_key("**"),),  # whatever drives a turtle it moves, in any namespace
)
