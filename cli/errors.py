"""What can go wrong for a user, and the exit code of each: the one table.

Logic modules raise the error that says what happened (``BadInput``, ``Unreachable``,
…), never an exit code; ``cli.main.main`` is the one place that prints the message
on stderr and exits with ``exit_code(error)``.
"""

from __future__ import annotations

import enum


class ExitCode(enum.IntEnum):
    OK = 0  # success: goal reached, messages printed, system stopped on request
    FAILED = 1  # ran, but did not succeed: goal not reached, a required node died
    BAD_INPUT = 2  # bad arguments or launch file; checked before anything is sent or started
    UNREACHABLE = 3  # nothing to talk to: no router, no navigator, no publisher
    CANNOT_START = 4  # launch could not start: the port is in use
    INTERRUPTED = 130  # stopped by Ctrl-C before finishing (goto)


class TurtlectlError(Exception):
    """An error for the user: one line of text (``message``)."""

    def __init__(self, message: str):
        super().__init__(message)
        self.message = message


class BadInput(TurtlectlError):
    """Arguments, a launch file or a payload that cannot be used; nothing was sent or started."""


class Unreachable(TurtlectlError):
    """Nothing to talk to: no router, nobody serving or publishing what was asked for."""


class CannotStart(TurtlectlError):
    """The system could not start: a port in use, a log folder that cannot be written."""


class Failed(TurtlectlError):
    """It ran but did not succeed: a goal not reached, a request refused."""


class Interrupted(TurtlectlError):
    """Stopped by Ctrl-C before it finished."""


EXIT_CODES: dict[type[TurtlectlError], ExitCode] = {
    BadInput: ExitCode.BAD_INPUT,
    Unreachable: ExitCode.UNREACHABLE,
    CannotStart: ExitCode.CANNOT_START,
    Failed: ExitCode.FAILED,
    Interrupted: ExitCode.INTERRUPTED,
}


def exit_code(error: TurtlectlError) -> ExitCode:
    """The exit code for ``error`` (its class or the nearest base in the table)."""
    for cls in type(error).__mro__:
        if cls in EXIT_CODES:
            return EXIT_CODES[cls]  # type: ignore[index]
    return ExitCode.FAILED
