"""``python -u -m runtime TARGET``: how a user's node runs (``run = "./patrol.py:Patrol"`` or
``"mypkg.patrol:Patrol"`` in a launch file, or ``turtlectl run``).

A user's node is always started by exec, a fresh interpreter running this module: it imports
the user's module or file (runtime.loader), then runs its class with its ``Params`` as a
built-in node module's ``main`` does (``run_main``: config, signals, supervisor death, exit
codes).  It is never forked by the zygote: the zygote imports the built-in node modules
before it forks, and a user's module may start threads or open files at import time, which a
fork would copy half-done (only the forking thread survives a fork).  Built-in kinds keep the
zygote; a user's node pays the interpreter's start-up instead.

Exit codes: 2 when the target names no usable node class (one line: why), 1 with the traceback
when the module's own code raises while it is imported (as a node that raises while starting;
the supervisor's respawn rules apply)."""

from __future__ import annotations

import logging
import sys
import traceback

from turtlectl.runtime.exitcodes import ExitCode
from turtlectl.runtime.lifecycle import run_main
from turtlectl.runtime.loader import ImportRaised, LoadError, load


def main(argv: list[str]) -> None:
    if len(argv) != 1:
        print("usage: python -m turtlectl.runtime module:Class | /path/to/file.py:Class", file=sys.stderr)
        sys.exit(ExitCode.BAD_INPUT)
    try:
        cls, params = load(argv[0])
    except ImportRaised as exc:
        traceback.print_exception(exc.__cause__ or exc, file=sys.stderr)
        sys.exit(ExitCode.FAILED)
    except LoadError as exc:
        logging.basicConfig(level=logging.INFO, format="%(levelname)s %(message)s", stream=sys.stderr)
        logging.getLogger("runtime").error("%s", exc)
        sys.exit(ExitCode.BAD_INPUT)
    run_main(cls, params)


if __name__ == "__main__":
    main(sys.argv[1:])
