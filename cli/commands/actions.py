"""turtlectl's goal services group: action list, info, send-goal (as ``ros2 action``).

Sessions (cli.tools) are imported inside the commands."""

from __future__ import annotations

from typing import Any

import typer

from turtlectl.cli.commands.options import ConnectOption, DomainOption, completer, format
from turtlectl.runtime.client.errors import Interrupted, goal_exit_code
from turtlectl.runtime.client.sigint import ignore_sigint

action_app = typer.Typer(
    help="Goal services, any node's (as `ros2 action`): list, info, send-goal.\n\nExample: turtlectl action list"
)


@action_app.command("list")
def action_list(
    json: bool = typer.Option(False, "--json", help="JSON."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Every running goal service with its goal, feedback and result types (as `ros2 action list -t`).

    Example: turtlectl action list
    """
    from turtlectl.cli.tools import actions

    rows = actions.goal_services(connect, domain)
    typer.echo(format.json_value(rows) if json else actions.rows_text(rows))


@action_app.command("info")
def action_info(
    service: str = typer.Argument(
        ..., metavar="KEY", autocompletion=completer("goal_services"), help="The goal service's key."
    ),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """A goal service: who serves it, its three types, its cancel service and feedback topic.

    Example: turtlectl action info navigate_to
    """
    from turtlectl.cli.tools import actions

    typer.echo(actions.row_text(actions.goal_service(connect, domain, service)))


@action_app.command("send-goal")
def send_goal(
    service: str = typer.Argument(
        ..., metavar="KEY", autocompletion=completer("goal_services"), help="The goal service's key."
    ),
    goal: str = typer.Argument("{}", metavar="JSON", help="The goal's fields as JSON."),
    feedback: bool = typer.Option(False, "--feedback", help="Print each feedback as it arrives."),
    timeout: float | None = typer.Option(
        None, "--timeout", min=0.1, help="Give up after S seconds (the goal is then canceled)."
    ),
    json: bool = typer.Option(False, "--json", help="JSON lines."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Send a goal to any goal service and print its result (as `ros2 action send_goal`).
    Ctrl-C (exit code 130) or --timeout cancels the goal through KEY/cancel (exit code 5 if
    nobody confirms it); a result whose `success` is false is exit code 1 (2 with reason
    "invalid goal": refused for itself).

    Example: turtlectl action send-goal patrol/laps '{"laps": 2}' --feedback
    """
    from turtlectl.cli.tools import actions
    from turtlectl.runtime.client import services

    def show(message: Any) -> None:
        if isinstance(message, services.Raw):
            typer.echo(message.payload.decode("utf-8", "replace"))
        else:
            typer.echo(format.message_json(message) if json else format.message_block(message))

    try:
        result = actions.send_goal(connect, domain, service, goal, timeout, show if feedback else None)
    except KeyboardInterrupt:
        raise Interrupted("interrupted") from None
    ignore_sigint()
    show(result)
    raise typer.Exit(goal_exit_code(result))


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.add_typer(action_app, name="action")
