"""turtlectl's ROS 2 commands: ``turtlectl ros2 bridge`` runs the bridge node (``run = "ros2_bridge"``,
nodes.ros2_bridge) by hand, as ``turtlectl run`` runs any node; ``turtlectl ros2 call`` calls a ROS 2
service over DDS.  The DDS side is imported by the node process and inside ``call``
(cli.tools.ros2_call), never on start-up."""

from __future__ import annotations

from pathlib import Path

import typer

from turtlectl.cli import args
from turtlectl.cli.commands.options import ConnectOption, DomainOption, LogLevelOption
from turtlectl.runtime.client import checks
from turtlectl.runtime.client.errors import CannotStart, ExitCode, Interrupted

ros2_app = typer.Typer(
    help="turtlectl in a ROS 2 graph (over DDS, on this host; the ros2 extra): the bridge, and calling ROS services.\n\n"
    "Example: turtlectl ros2 bridge --ros-domain 7"
)

INSTALL_HINT = "pip install 'turtlectl[ros2]'"


@ros2_app.command()
def bridge(
    ros_domain: int | None = typer.Option(
        None, "--ros-domain", min=0, max=232, help="ROS 2 domain id (default: ROS_DOMAIN_ID, else 0)."
    ),
    address: str = typer.Option("127.0.0.1", "--address", help="The only address DDS uses (loopback by default)."),
    turtle: list[str] = typer.Option([], "--turtle", help="Bridge only this turtle (repeatable; default: every one)."),
    param: list[str] = typer.Option(
        [], "--param", "-p", help="KEY=VALUE of the bridge's parameters (repeatable), as in a launch file."
    ),
    name: str = typer.Option("ros2_bridge", "--name", help="The bridge's node name, in turtlectl and in ROS 2."),
    log_level: str = LogLevelOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Put the running system into a ROS 2 graph: each turtle's cmd_vel (both ways), pose, odometry,
    scan and status, the clock and the log, as rclpy and ROS 2's tools see them (docs/how-to/ros2.md).
    Runs in the foreground until Ctrl-C; exit code 4 without the DDS side (the ros2 extra).

    Example: turtlectl ros2 bridge --turtle turtle2 -p defaults=true
    """
    import importlib.util

    from turtlectl.cli.system.overrides import class_plan, node_config
    from turtlectl.cli.system.supervisor.process import exec_node

    if importlib.util.find_spec("cyclonedds") is None:
        raise CannotStart(f"the ROS 2 bridge needs Eclipse Cyclone DDS, not installed here: {INSTALL_HINT}")
    level = args.log_level(log_level)
    endpoint = checks.endpoint(connect)
    overrides = [*param, f"address={address}"]
    if ros_domain is not None:
        overrides.append(f"ros_domain={ros_domain}")
    if turtle:
        overrides.append("turtles=[" + ", ".join(f'"{t}"' for t in turtle) + "]")
    plan, named = class_plan("ros2_bridge", overrides, Path.cwd(), name)
    typer.echo(f"running the ROS 2 bridge as node {named} (Ctrl-C stops it)", err=True)
    exec_node(node_config(plan, named, endpoint, None, domain, level), plan.kinds[named])


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
    """Add this group's commands to ``app``."""
    app.add_typer(ros2_app, name="ros2")
