"""Parameters of the simulator process (set in the launch file's ``[node.params]``)."""

from __future__ import annotations

import msgspec

from messages.units import Finite, ShortTimeout
from messages.world import TURTLESIM_SIZE


class SimParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """x, y: spawn position, m (turtlesim's centre by default), inside the world and outside
    every obstacle (the launch file's validation checks both).  theta: spawn heading, rad.
    cmd_timeout: s after the last cmd_vel at which the turtle stops (turtlesim: 1 s; 0.05 to
    60, as commands come with each 16 ms pose while a goal runs).
    """

    x: Finite = TURTLESIM_SIZE / 2.0
    y: Finite = TURTLESIM_SIZE / 2.0
    theta: Finite = 0.0
    cmd_timeout: ShortTimeout = 1.0
