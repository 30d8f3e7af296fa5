"""Constrained numbers for parameters and the world model (pure: no zenoh).

Validated, with the key path, when a launch file or a node's config is converted.
"""

from __future__ import annotations

from typing import Annotated

import msgspec

# Constrained numbers for parameters: validated (with the key path) when a
# launch file is converted; NaN fails every bound, 1e9 stands in for "finite".
Finite = Annotated[float, msgspec.Meta(ge=-1e9, le=1e9)]
Positive = Annotated[float, msgspec.Meta(gt=0.0, le=1e9)]
NonNegative = Annotated[float, msgspec.Meta(ge=0.0, le=1e9)]
Percent = Annotated[float, msgspec.Meta(ge=0.0, le=100.0)]

# Rates and times, bounded so that a typo cannot make a node spin (1e9 Hz) or wait forever:
#: Hz of a node's timer (status 10 Hz, scan 5 Hz, goal feedback 10 Hz): 0.1 to 100.
Rate = Annotated[float, msgspec.Meta(ge=0.1, le=100.0)]
#: s of a watchdog on a fast stream (poses and commands every 16 ms, scans every 200 ms): 0.05 to 60.
ShortTimeout = Annotated[float, msgspec.Meta(ge=0.05, le=60.0)]
#: simulated seconds per wall second (the simulator's real_time_factor)
TimeFactor = Annotated[float, msgspec.Meta(ge=0.1, le=20.0)]
#: s of a goal-level limit (blocked, whole goal): 0.1 s to an hour.
LongTimeout = Annotated[float, msgspec.Meta(ge=0.1, le=3600.0)]
