"""Exit codes of every turtlectl command, and the one error type that carries them.

Commands raise ``CliError``; ``cli.main.main`` is the one place that turns it
into a message on stderr and an exit code.
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


class CliError(Exception):
    """An error for the user: one line, and the exit code it maps to."""

    def __init__(self, code: ExitCode, message: str):
        super().__init__(message)
        self.code = code
        self.message = message
