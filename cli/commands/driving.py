"""turtlectl's Goals and driving commands: goto, cancel, teleport, reset, teleop.

Sessions, goals and the keyboard (cli.tools) are imported inside each command."""

from __future__ import annotations

import shutil
import sys

import typer

from turtlectl.cli import args
from turtlectl.cli.commands.options import ConnectOption, DomainOption, ExitOnLossOption, TurtleOption, format, result
from turtlectl.runtime.client.errors import (
    ExitCode,
    Failed,
    GoalCanceled,
    Interrupted,
    goal_exit_code,
)


def goto(
    x: str = typer.Argument(..., metavar="X", help="Goal x, m."),
    y: str = typer.Argument(..., metavar="Y", help="Goal y, m."),
    theta: str = typer.Argument(..., metavar="THETA", help="Goal heading, degrees (negative values are fine)."),
    timeout: float | None = typer.Option(
        None,
        "--timeout",
        min=0.1,
        help="Stop waiting (and cancel the goal) after S seconds; default: the navigator's goal_timeout.",
    ),
    json: bool = typer.Option(False, "--json", help="Print the response as one JSON object."),
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Send the turtle to (X, Y) facing THETA degrees and wait for the outcome (--turtle turtle2:
    turtle2's navigator, turtle2/navigate_to).

    On a terminal a live progress line shows the goal's state; piped, only the
    outcome is printed.  Ctrl-C or --timeout cancels the goal (exit code 130 or 1), and
    exit code 5 says that nobody confirmed the cancel: the turtle may still be driving.  A goal
    refused for itself (outside the world, inside or too near an obstacle) is exit code 2, as a
    teleport there; any other goal not reached, 1.

    Example: turtlectl goto 8 5 90   or   turtlectl goto 2 2 0 --turtle turtle2
    """
    from turtlectl.messages import NavigateToFeedback
    from turtlectl.runtime.client import goals
    from turtlectl.runtime.client.api import Client

    goal = args.finite_number(x, "x"), args.finite_number(y, "y"), args.finite_number(theta, "theta")
    live = sys.stdout.isatty() and not json

    def show(fb: NavigateToFeedback) -> None:  # the terminal's width now: it may be resized meanwhile
        typer.echo("\r\033[K" + format.progress_line(fb, shutil.get_terminal_size().columns), nl=False)

    try:
        with Client(connect, domain, turtle, timeout_named=goals.CLI_LIMIT) as client:
            response = client.goto(*goal, timeout=timeout, on_feedback=show if live else None)
    except KeyboardInterrupt:  # before the goal was sent (one running is canceled and checked in run_goal)
        raise Interrupted("interrupted") from None
    except GoalCanceled as canceled:
        if canceled.timeout is not None or canceled.response is None:  # --timeout's: an error, in its words
            raise
        response = canceled.response  # canceled by anyone: the navigator's outcome, as any goal not reached
    finally:
        if live:
            typer.echo("\r\033[K", nl=False)
    result(format.message_json(response) if json else format.outcome_line(response))
    raise typer.Exit(goal_exit_code(response))


def cancel(turtle: str = TurtleOption, connect: str = ConnectOption, domain: str = DomainOption) -> None:
    """Cancel the running goal (of --turtle's navigator): the turtle brakes at once; its caller
    gets reason "canceled".

    Exit code 1 if no goal was running.

    Example: turtlectl cancel
    """
    from turtlectl.runtime.client.api import Client

    with Client(connect, domain, turtle) as client:
        ack = client.cancel()
    result(ack.detail)
    raise typer.Exit(ExitCode.OK if ack.ok else ExitCode.FAILED)


def teleport(
    x: str = typer.Argument(..., metavar="X", help="x, m."),
    y: str = typer.Argument(..., metavar="Y", help="y, m."),
    theta: str = typer.Argument(..., metavar="THETA", help="Heading, degrees (as for goto)."),
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Put the turtle at (X, Y) facing THETA degrees, at rest (turtlesim's teleport_absolute).

    Example: turtlectl teleport 2 2 45
    """
    from turtlectl.messages import Ack, TeleportAbsolute, keys
    from turtlectl.messages.angles import heading_radians
    from turtlectl.runtime.client.api import Client

    degrees = args.finite_number(theta, "theta")
    request = TeleportAbsolute(
        x=args.finite_number(x, "x"), y=args.finite_number(y, "y"), theta=heading_radians(degrees)
    )
    with Client(connect, domain) as client:  # the simulator's key for the turtle: no namespace
        replies = client.call_all(keys.teleport_key(turtle or keys.FIRST_TURTLE), request)
    acks = [a for a in replies if isinstance(a, Ack)]
    if not all(a.ok for a in acks):  # the simulator's own words (they are in radians, as its request)
        raise Failed(format.ack_lines(acks))
    line = format.teleport_line(request.x, request.y, degrees)
    result(f"{turtle} {line}" if turtle else line)


def reset(connect: str = ConnectOption, domain: str = DomainOption) -> None:
    """Put turtle1 back at its spawn pose (again if it was killed), remove every spawned turtle,
    and fill the battery (turtlesim's reset).

    Example: turtlectl reset
    """
    from turtlectl.messages import Ack, Reset, keys
    from turtlectl.runtime.client.api import Client

    with Client(connect, domain) as client:
        acks = [a for a in client.call_all(keys.RESET, Reset(), everyone=True) if isinstance(a, Ack)]
    result(format.reset_lines(acks))
    raise typer.Exit(ExitCode.OK if all(a.ok for a in acks) else ExitCode.FAILED)


def teleop(
    linear: float = typer.Option(2.0, "--linear", min=0.0, help="Speed of up/down (w/s), m/s."),
    angular: float = typer.Option(2.0, "--angular", min=0.0, help="Turn rate of left/right (a/d), rad/s."),
    force: bool = typer.Option(
        False,
        "--force",
        help="Drive even if another client (a teleop, pub, a script) drives the turtle: both are warned.",
    ),
    exit_on_loss: bool = ExitOnLossOption,
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Drive the turtle from the keyboard, as turtlesim's teleop_turtle_key: arrow keys or
    w/a/s/d (a held key keeps the turtle going; it stops 0.7 s after the key is released),
    space stops (and cancels a running goal), q or Ctrl-C quits (exit code 0).  A goal
    running when the keys start driving is canceled (reason "teleop").  The status line
    shows the command being sent and the turtle's pose.  Its input must be a terminal
    (exit code 2 otherwise).  A turtle another client drives already (a second teleop on
    it) is refused, naming that client, its pid and host (exit code 4), unless --force:
    then both are warned.  A lost router stops the driving (nothing is sent until it is
    back and a key is pressed), said on the status line; --exit-on-loss exits with code 3
    instead.

    Example: turtlectl teleop --linear 1.0
    """
    from turtlectl.cli.tools.teleop import run_teleop, terminal_fd
    from turtlectl.runtime.client.api import Client

    args.finite_option(linear, "--linear")
    args.finite_option(angular, "--angular")
    fd = terminal_fd(sys.stdin)
    with Client(connect, domain, turtle) as client:
        run_teleop(client.session, linear, angular, client.connect, fd, sys.stdout, client.driven, force, exit_on_loss)


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.command(context_settings={"ignore_unknown_options": True})(goto)
    app.command()(cancel)
    app.command(context_settings={"ignore_unknown_options": True})(teleport)
    app.command()(reset)
    app.command()(teleop)
