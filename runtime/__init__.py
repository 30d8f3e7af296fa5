"""What every turtlectl process uses: the node API (publishers, subscriptions, services,
timers, liveliness) on one logic thread, the process lifecycle, session configuration and
the node config the supervisor hands over.  Imports ``messages`` only, never sim/nodes/cli.

The node API is loaded when first used (``from runtime import Node``), not when a module
of the package is imported: ``runtime.session``'s constants and ``runtime.config`` stay
cheap for the command line (``turtlectl --help``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from turtlectl import _lazy

if TYPE_CHECKING:
    from turtlectl.runtime.entities import Latest, Publisher, Request, Timer
    from turtlectl.runtime.lifecycle import run, run_main
    from turtlectl.runtime.node import Node, NodeConflict

__all__ = ["Latest", "Node", "NodeConflict", "Publisher", "Request", "Timer", "run", "run_main"]

_HOME = {
    "Latest": "turtlectl.runtime.entities",
    "Node": "turtlectl.runtime.node",
    "NodeConflict": "turtlectl.runtime.node",
    "Publisher": "turtlectl.runtime.entities",
    "Request": "turtlectl.runtime.entities",
    "Timer": "turtlectl.runtime.entities",
    "run": "turtlectl.runtime.lifecycle",
    "run_main": "turtlectl.runtime.lifecycle",
}


__getattr__ = _lazy(__name__, _HOME)
