"""``turtlectl web``: the world, goals by pointing, the keyboard and rqt's panels in a browser
(cli.web).  It runs the page's node by hand, as ``turtlectl run`` runs any node and as
``run = "web"`` in a launch file runs it."""

from __future__ import annotations

from pathlib import Path

import typer

from turtlectl.cli import args
from turtlectl.cli.commands.options import ConnectOption, DomainOption, LogLevelOption
from turtlectl.runtime.client import checks


def web(
    port: int = typer.Option(8080, "--port", min=1, max=65535, help="The page's TCP port: http://HOST:PORT/."),
    host: str = typer.Option(
        "127.0.0.1", "--host", help="Where the page listens (loopback by default; 0.0.0.0: every address)."
    ),
    role: str = typer.Option(
        "",
        "--role",
        help="On a --secure system, the login the page uses: viewer, operator or teleop "
        "(default: TURTLECTL_ROLE, else operator); the page can do what the role may, no more.",
    ),
    insecure: bool = typer.Option(
        False, "--insecure", help="Let --host reach beyond this machine: the page has no logins of its own."
    ),
    name: str = typer.Option("web", "--name", help="The page's node name."),
    log_level: str = LogLevelOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Serve a page of the running system: the world drawn live (turtles, trails, scans, goals),
    drag on the map to send a goal (rviz's 2D Goal Pose), arrows or WASD to drive, and the nodes,
    topics, live echo, plot, log and parameters beside it (docs/how-to/web.md).  Runs in the
    foreground until Ctrl-C; exit code 3 if no system runs at --connect, 4 if the port is taken.

    Example: turtlectl web --port 8080   (then open http://127.0.0.1:8080/)
    """
    from turtlectl.cli.system.overrides import class_plan, node_config
    from turtlectl.cli.system.supervisor.process import exec_node

    level = args.log_level(log_level)
    endpoint = checks.endpoint(connect)
    from turtlectl.runtime.client import credentials
    from turtlectl.runtime.client.errors import BadInput

    if role and role not in credentials.ROLES:
        raise BadInput(f"--role {role!r} is not a role (roles: {', '.join(credentials.ROLES)})")
    from turtlectl.nodes.params import WebParams

    try:
        WebParams(host=host, port=port, role=role or credentials.role(), insecure=insecure)  # type: ignore[arg-type]
    except ValueError as exc:
        raise BadInput(str(exc)) from None
    from turtlectl.runtime.client.session import probe

    probe(endpoint)  # no system there: the line every client command says (exit 3), before the page starts
    overrides = [f"port={port}", f'host="{host}"', f'role="{role or credentials.role()}"']
    if insecure:
        overrides.append("insecure=true")
    plan, named = class_plan("web", overrides, Path.cwd(), name)
    exec_node(node_config(plan, named, endpoint, None, domain, level), plan.kinds[named])


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.command()(web)
