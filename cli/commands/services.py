"""turtlectl's Services command: call.

Sessions and requests from JSON (cli.tools) are imported inside the command."""

from __future__ import annotations

from typing import Any

import typer

from turtlectl.cli.commands.options import ConnectOption, DomainOption, completer, format
from turtlectl.runtime.client.errors import ExitCode, Interrupted
from turtlectl.runtime.client.sigint import ignore_sigint


def call(
    service: str = typer.Argument(
        ..., metavar="SERVICE", autocompletion=completer("services"), help="Key of the queryable."
    ),
    request: str = typer.Argument("{}", metavar="JSON", help="The request's fields as JSON."),
    timeout: float | None = typer.Option(
        None,
        "--timeout",
        min=0.1,
        help="Give up after S seconds (a goal is then canceled); default 5, for navigate_to the navigator's goal_timeout.",
    ),
    type_name: str | None = typer.Option(None, "--type", help="Request type, for keys without a known one."),
    json: bool = typer.Option(False, "--json", help="JSON lines."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Call any queryable: known services get a typed request, others the JSON as is.
    Replies are printed as they arrive (navigate_to: its feedback, then its response).
    A missing service is reported within 3 s.

    As goto and cancel: navigate_to holds a client token, and Ctrl-C (exit code 130) or
    --timeout cancels the goal through navigate_to/cancel (exit code 5 if nobody confirms
    it); an Ack with ok false or a response with success false is exit code 1.
    Example: turtlectl call turtle1/teleport_absolute '{"x": 2, "y": 2, "theta": 0}'
    """
    from turtlectl.cli.tools import build, topics
    from turtlectl.runtime.client import services
    from turtlectl.runtime.client import session as client

    key = client.check_key(service)
    type_name = topics.learn_type(
        connect, domain, client.base_key(key, domain), type_name
    )  # yours: from the nodes using it
    body = build.service_request(client.base_key(key, domain), request, type_name)

    def show(reply: Any) -> None:
        if isinstance(reply, services.Raw):
            typer.echo(reply.payload.decode("utf-8", "replace"))
        else:
            typer.echo(format.message_json(reply) if json else format.message_block(reply))

    code = ExitCode.OK
    try:  # a goal's feedback is shown from inside the call: a Ctrl-C there cancels the goal and checks
        for reply in services.call_service(connect, domain, key, body, timeout, on_feedback=show):
            ignore_sigint()  # an answer (feedback never comes here): a Ctrl-C from now on changes nothing
            show(reply)
            if not isinstance(reply, services.Raw):
                code = max(code, services.reply_code(reply))
    except KeyboardInterrupt:
        raise Interrupted("interrupted") from None
    raise typer.Exit(code)


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.command()(call)
