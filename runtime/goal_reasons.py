"""Why a goal server (runtime.goals) ends a goal: the ``reason`` its ``on_cancel(goal, reason)``
is told, and the reason of a goal refused for itself.  A ``Cancel``'s own reason (teleop's "teleop") is passed
on as it is.  Pure: a node's pure goal logic (nodes.goal_machine) reads them too."""

from __future__ import annotations

PREEMPTED = "preempted"  # a newer goal replaced it
CANCELED = "canceled"  # KEY/cancel, without a reason of its own
CALLER_GONE = "caller gone"  # its caller's liveliness token vanished
TIMEOUT = "timeout"  # not finished within the server's timeout
SHUT_DOWN = "shut down"  # the node stops, or the goal server is undeclared
INVALID_GOAL = (
    "invalid goal"  # refused for itself (not finite, outside the world, in or too near an obstacle): exit code 2
)
