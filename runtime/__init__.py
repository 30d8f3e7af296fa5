"""What every turtlectl process uses: the node API (publishers, subscriptions, services,
timers, liveliness) on one logic thread, the process lifecycle, session configuration and
the node config the supervisor hands over.  Imports ``messages`` only, never sim/nodes/cli."""

from runtime.lifecycle import run, run_main
from runtime.node import Node, NodeConflict, Publisher, Request

__all__ = ["Node", "NodeConflict", "Publisher", "Request", "run", "run_main"]
