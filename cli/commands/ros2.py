"""turtlectl's ROS 2 commands (``turtlectl ros2 ...``): talking to a ROS 2 graph over DDS.

Cyclone DDS is imported inside the commands (cli.tools.ros2_call), never on start-up."""

from __future__ import annotations

import typer

from turtlectl.runtime.client.errors import ExitCode, Interrupted

ros2_app = typer.Typer(
    help="A ROS 2 graph over DDS (ROS_DOMAIN_ID, on this host): call its services.\n\n"
    "Example: turtlectl ros2 call /set_flag std_srvs/srv/SetBool '{data: true}'"
)

DEFAULT_TIMEOUT = 5.0  # s for a server to match and answer


@ros2_app.command("call")
def call(
    service: str = typer.Argument(..., metavar="SERVICE", help="The ROS service, as /set_flag."),
    service_type: str = typer.Argument(..., metavar="TYPE", help="Its type, as std_srvs/srv/SetBool."),
    request: str = typer.Argument("{}", metavar="VALUES", help="The request, as '{data: true}' (YAML or JSON)."),
    timeout: float = typer.Option(
        DEFAULT_TIMEOUT, "--timeout", min=0.1, help="Give up after S seconds without a server or an answer."
    ),
    json: bool = typer.Option(False, "--json", help="The response as one JSON object."),
) -> None:
    """Call a ROS 2 service, as `ros2 service call`: the request on DDS, the response printed.

    Types: std_srvs/srv/Empty, SetBool, Trigger; turtlesim/srv/Spawn, Kill, TeleportAbsolute,
    TeleportRelative, SetPen.  Fields not given take their defaults (false, 0, "").  The domain is
    ROS_DOMAIN_ID's (0 unless set); discovery stays on 127.0.0.1.  Exit code 3 if no server
    answers within --timeout, 2 for an unknown type or a request that does not fit it, 1 for a
    response whose success is false.  One call at a time: a reply the server sends another
    client of the same service at that moment would be taken for this one.

    Example: turtlectl ros2 call /set_flag std_srvs/srv/SetBool '{data: true}'
    """
    from turtlectl.cli.tools import ros2_call

    try:
        response = ros2_call.call(service, service_type, request, timeout)
    except KeyboardInterrupt:
        raise Interrupted("interrupted") from None
    if json:
        from turtlectl.cli.tools.format import json_value

        typer.echo(json_value(response))
    else:
        typer.echo(ros2_call.response_text(service, service_type, response))
    raise typer.Exit(ExitCode.FAILED if response.get("success") is False else ExitCode.OK)


def register(app: typer.Typer) -> None:
    """Add the ``ros2`` group to ``app``."""
    app.add_typer(ros2_app, name="ros2")
