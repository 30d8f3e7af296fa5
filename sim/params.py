"""Parameters of the simulator process (set in the launch file's ``[node.params]``)."""

from __future__ import annotations

from typing import ClassVar

import msgspec

from turtlectl.messages.units import Finite, ShortTimeout
from turtlectl.messages.world import TURTLESIM_SIZE


class SimParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """The simulator: where the turtle spawns (inside the world and outside every obstacle:
    the launch file's validation checks both) and when it stops without commands
    (``# unit: meaning`` per field)."""

    x: Finite = TURTLESIM_SIZE / 2.0  # m: spawn position (turtlesim's centre by default)
    y: Finite = TURTLESIM_SIZE / 2.0  # m: spawn position
    theta: Finite = 0.0  # rad: spawn heading
    cmd_timeout: ShortTimeout = 1.0  # s: after the last cmd_vel the turtle stops (turtlesim: 1 s)

    FIXED: ClassVar[dict[str, str]] = {
        name: "the spawn pose is read once, at start (`turtlectl teleport` moves the turtle)"
        for name in ("x", "y", "theta")
    }
