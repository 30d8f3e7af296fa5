"""What can go wrong for a user, and the exit code of each (the numbers: the one table of
every turtlectl process, ``runtime.exitcodes.ExitCode``, which node processes use too).

Logic modules raise the error that says what happened (``BadInput``, ``Unreachable``,
…), never an exit code; ``cli.main.main`` is the one place that prints the message
on stderr and exits with ``exit_code(error)``.
"""

from __future__ import annotations

from typing import Any

import turtlectl.runtime.goal_reasons as goal_reasons
from turtlectl.runtime.exitcodes import ExitCode

__all__ = [
    "BadInput",
    "CancelUnconfirmed",
    "CannotStart",
    "ExitCode",
    "Failed",
    "GoalCanceled",
    "Interrupted",
    "TurtlectlError",
    "Unreachable",
    "exit_code",
    "goal_exit_code",
]


class TurtlectlError(Exception):
    """An error for the user: one line of text (``message``); public as ``turtlectl.Error``."""

    def __init__(self, message: str):
        super().__init__(message)
        self.message = message

    @property
    def said(self) -> str:
        """What went wrong, without the advice its message adds in parentheses (for a line that
        mentions it in passing); the message itself for an error without advice."""
        return self.message

    @property
    def exit_code(self) -> ExitCode:
        """The exit code the command line ends with for this error (docs/reference/exit-codes.md)."""
        return exit_code(self)


class BadInput(TurtlectlError):
    """Arguments, a launch file or a payload that cannot be used; nothing was sent or started."""


class Unreachable(TurtlectlError):
    """Nothing to talk to: no router, nobody serving or publishing what was asked for."""


class CannotStart(TurtlectlError):
    """The system could not start: a port in use, a log folder that cannot be written."""


class Failed(TurtlectlError):
    """It ran but did not succeed: a goal not reached, a request refused."""


class Interrupted(TurtlectlError):
    """Stopped by Ctrl-C before it finished; for a goal, ``feedback`` is its last (None: none came)."""

    feedback: Any = None


class CancelUnconfirmed(TurtlectlError):
    """A goal was given up on (a timeout, Ctrl-C) and nobody confirmed its cancel: the turtle
    may still be driving to it.  ``feedback``: what its last feedback said (where the turtle
    was then; None: none came)."""

    feedback: Any = None


class GoalCanceled(Failed):
    """A goal canceled before it ended (exit code 1, as a goal not reached), as a future's
    ``CancelledError``: by the caller's own ``timeout`` (``timeout``: those s; None: a cancel
    from anyone, ``Client.cancel`` or ``turtlectl cancel``).  ``response``: the server's result
    (a ``NavigateToResponse``: the final pose, ``reason`` "canceled"; None if it sent none
    within 2 s of the cancel); ``feedback``: the goal's last feedback (None: none came);
    ``outcome``: what the server said of the cancel ("the navigator canceled the goal")."""

    def __init__(
        self,
        message: str,
        response: Any = None,
        feedback: Any = None,
        timeout: float | None = None,
        outcome: str = "",
    ):
        super().__init__(message)
        self.response = response
        self.feedback = feedback
        self.timeout = timeout
        self.outcome = outcome


EXIT_CODES: dict[type[TurtlectlError], ExitCode] = {
    BadInput: ExitCode.BAD_INPUT,
    Unreachable: ExitCode.UNREACHABLE,
    CannotStart: ExitCode.CANNOT_START,
    Failed: ExitCode.FAILED,
    Interrupted: ExitCode.INTERRUPTED,
    CancelUnconfirmed: ExitCode.CANCEL_UNCONFIRMED,
}


def exit_code(error: TurtlectlError) -> ExitCode:
    """The exit code for ``error`` (its class or the nearest base in the table)."""
    for cls in type(error).__mro__:
        if cls in EXIT_CODES:
            return EXIT_CODES[cls]  # type: ignore[index]
    return ExitCode.FAILED


def goal_exit_code(result: object) -> ExitCode:
    """The exit code of a goal's result (``NavigateToResponse``, or any result with ``success``
    and ``reason``): 0 reached; 2 (bad input) refused for the goal itself, reason "invalid goal"
    (not finite, outside the world, inside or too near an obstacle: what a teleport there is
    refused for, with the same code); 1 any other end (unreachable, battery low, blocked,
    canceled, timeout, ...)."""
    if getattr(result, "success", True) is not False:
        return ExitCode.OK
    return ExitCode.BAD_INPUT if getattr(result, "reason", "") == goal_reasons.INVALID_GOAL else ExitCode.FAILED
