"""The ``turtlectl`` command line: launch supervisor and client tools.

``entry`` is the console script.  It is kept apart from ``cli.main`` so that a
Ctrl-C while typer and a command's modules are imported ends the process with
one line instead of a traceback from inside an import.
"""

from __future__ import annotations

import importlib.util
import os
import signal
import sys
import time
from types import FrameType, ModuleType

from turtlectl.runtime.client.errors import ExitCode

#: when this command began (time.monotonic, s): the first thing the console script runs, so that
#: `launch` can say how long its nodes took to be ready from the user's point of view
STARTED = time.monotonic()

#: commands for which Ctrl-C is the normal way to stop: exit 0, as README's exit codes say
STOPPED_BY_CTRL_C = ("launch", "router")


#: root options whose value is the next word (``--domain=x`` needs nothing skipped)
_ROOT_OPTIONS_WITH_VALUE = ("--domain", "--connect")


def lazy_module(name: str) -> ModuleType:
    """Module ``name``, imported on first attribute access (importlib's LazyLoader): what only
    some commands use costs nothing to the others, ``--help`` included."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.find_spec(name)
    if spec is None or spec.loader is None:
        raise ImportError(f"no module named {name!r}")
    loader = importlib.util.LazyLoader(spec.loader)
    spec.loader = loader
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    loader.exec_module(module)
    return module


def command_of(argv: list[str]) -> str:
    """The command word of a turtlectl command line (after root options), or ''."""
    args = iter(argv)
    for arg in args:
        if arg in _ROOT_OPTIONS_WITH_VALUE:
            next(args, None)
        elif not arg.startswith("-"):
            return arg
    return ""


def _interrupted_while_starting(_signum: int, _frame: FrameType | None) -> None:
    command = command_of(sys.argv[1:])
    os.write(2, b"turtlectl: interrupted while starting; nothing was started\n")
    os._exit(ExitCode.OK if command in STOPPED_BY_CTRL_C else ExitCode.INTERRUPTED)


def entry() -> None:
    """Console entry point: quiet on Ctrl-C until a command takes SIGINT over (client
    commands get KeyboardInterrupt back in cli.main's root callback, the supervisor and
    the router install their own handlers)."""
    signal.signal(signal.SIGINT, _interrupted_while_starting)
    if command_of(sys.argv[1:]) == "launch" and not {"--help", "-h", "--check"} & set(sys.argv):
        # the zygote imports the nodes' modules while this process imports typer (2 cores)
        from turtlectl.cli.system.supervisor import zygote

        zygote.start_early()
    from turtlectl.cli.main import main

    main()
