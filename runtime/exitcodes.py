"""The one table of exit codes, for every turtlectl process: a command (``runtime.client.errors`` maps its
errors here, ``cli.main.main`` exits with the code) and a node process (``runtime.lifecycle``)
give each number the same meaning.  docs/reference/exit-codes.md documents it (docs/gen_exitcodes.py).

Pure: no zenoh, no I/O (the command line imports it at once).
"""

from __future__ import annotations

import enum
import signal


class ExitCode(enum.IntEnum):
    #: success: a goal reached, messages printed, a system or node stopped on request
    OK = 0
    #: ran but did not succeed: a goal not reached, an answer that says no, a required node
    #: died; a node: its own code raised (a crash)
    FAILED = 1
    #: what it was given cannot be used, nothing was sent or started: a command's arguments or
    #: launch file; a node's configuration, or a declaration outside its interface
    BAD_INPUT = 2
    #: nothing to talk to: no router, nobody serving or publishing what was asked for, a node that
    #: runs but does not answer (its thread busy or blocked); a node:
    #: no Zenoh session to the router
    UNREACHABLE = 3
    #: could not start: a port or a role another process already holds (launch's port, a second
    #: navigator serving navigate_to), a log folder that cannot be written, or an optional
    #: extra a command needs that is not installed (ros2: Cyclone DDS)
    CANNOT_START = 4
    #: a goal given up on (--timeout, Ctrl-C) whose cancel nobody confirmed: the turtle may
    #: still be driving to it
    CANCEL_UNCONFIRMED = 5
    #: interrupted by Ctrl-C before its result
    INTERRUPTED = 130


#: what a node's exit with each code means, as the supervisor says it
_NODE_MEANINGS = {
    ExitCode.BAD_INPUT: "bad input: its configuration or its declarations cannot be used",
    ExitCode.CANNOT_START: "could not start: another process already holds what it claims",
}


def respawn_can_help(code: int) -> bool:
    """Whether starting a node again could end otherwise than its exit with ``code`` (a signal:
    minus its number).  A configuration that cannot be used, or what another process holds,
    is the same at the next start: those are given up on at once; a crash, a lost session or
    a signal is worth a respawn."""
    return code not in _NODE_MEANINGS


def node_exit(code: int) -> str:
    """How a node's process ended, for the supervisor's line ("exited with code 4 (could not
    start: …)", "was killed by SIGKILL")."""
    if code < 0:
        try:
            return f"was killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"was killed by signal {-code}"
    meaning = _NODE_MEANINGS.get(code)  # type: ignore[call-overload]
    return f"exited with code {code}" + (f" ({meaning})" if meaning else "")
