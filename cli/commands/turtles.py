"""turtlectl's commands for several turtles, as turtlesim's services: spawn, kill (thin over
the simulator's ``spawn`` and ``kill``; sessions imported inside each command)."""

from __future__ import annotations

import typer

from turtlectl.cli import args
from turtlectl.cli.commands.options import ConnectOption, DomainOption, completer, result
from turtlectl.runtime.client.errors import Failed


def spawn(
    x: str = typer.Argument(..., metavar="X", help="x, m."),
    y: str = typer.Argument(..., metavar="Y", help="y, m."),
    theta: str = typer.Argument(..., metavar="THETA", help="Heading, degrees (as for goto)."),
    name: str = typer.Option("", "--name", help="Its name (default: the first free turtleN)."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Add a turtle at (X, Y) facing THETA degrees (turtlesim's spawn); prints its name.  Its
    keys are under its name: NAME/cmd_vel, NAME/pose, NAME/teleport_absolute.  Refused (exit
    code 2, with the reason) outside the world, inside an obstacle, on another turtle, or for a
    name taken.

    Example: turtlectl spawn 2 2 90 --name turtle2
    """
    from turtlectl.messages import SpawnRequest, SpawnResponse, keys
    from turtlectl.messages.angles import heading_radians
    from turtlectl.runtime.client.api import Client

    degrees = args.finite_number(theta, "theta")
    request = SpawnRequest(
        x=args.finite_number(x, "x"), y=args.finite_number(y, "y"), theta=heading_radians(degrees), name=name
    )
    with Client(connect, domain) as client:
        answers = [m for m in client.call_all(keys.SPAWN, request) if isinstance(m, SpawnResponse)]
    if not answers:
        raise Failed("the simulator did not say which turtle it spawned")
    result(answers[-1].name)


def kill(
    name: str = typer.Argument(
        ..., metavar="NAME", autocompletion=completer("turtles"), help="The turtle to remove (turtle2, ...)."
    ),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Remove turtle NAME and its keys (turtlesim's kill).  Exit code 2 for a turtle that does
    not exist (the message names those that do).

    Example: turtlectl kill turtle2
    """
    from turtlectl.messages import Ack, Kill, keys
    from turtlectl.runtime.client.api import Client

    with Client(connect, domain) as client:
        acks = [a for a in client.call_all(keys.KILL, Kill(name=name)) if isinstance(a, Ack)]
    if not acks:
        raise Failed("the simulator did not confirm the kill")
    result(acks[-1].detail)


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.command(context_settings={"ignore_unknown_options": True})(spawn)
    app.command()(kill)
