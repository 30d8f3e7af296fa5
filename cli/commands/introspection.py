"""turtlectl's Introspection commands: list, node info, log (cli.commands.logs), interface list and show, view.

The graph, node reports, message types and the curses view (cli.tools) are imported inside
each command."""

from __future__ import annotations

import typer

from turtlectl.cli.commands import logs
from turtlectl.cli.commands.options import (
    ConnectOption,
    DomainOption,
    ExitOnLossOption,
    JsonOption,
    NodeArgument,
    TurtleOption,
    format,
    result,
)


def list_graph(
    json: bool = typer.Option(False, "--json", help="The graph as one JSON object."),
    all_: bool = typer.Option(
        False, "--all", help="Also each node's own services (parameters, node info, log level) and log topic."
    ),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """The live graph: nodes (name, pid, host, uptime), the clients with a session open
    (command-line tools and scripts: name, tool, pid, host, uptime; the one asking is not
    listed), topics with their publishers and subscribers (clients' among them), and
    services; read from liveliness tokens now, never from a cache.
    Without --domain, systems running in domains are listed too, their names and keys
    prefixed with the domain (lab1:sim, lab1/robot/status).  The services and log topic every
    node has (turtlectl/params/<node>, turtlectl/nodes/<node>, turtlectl/log/<node>, ...) are
    counted, not listed, unless --all.

    Example: turtlectl list
    """
    from turtlectl.cli.tools import topics
    from turtlectl.runtime.client.graph import graph_text, without_node_services

    current = topics.graph(connect, domain)
    if not all_:
        current = without_node_services(current)
    result(format.json_value(current) if json else graph_text(current))


node_app = typer.Typer(help="Running nodes in detail (as `ros2 node`).\n\nExample: turtlectl node info navigator")


@node_app.command("list")
def node_list(json: bool = JsonOption, connect: str = ConnectOption, domain: str = DomainOption) -> None:
    """The running nodes' names, one per line (as `ros2 node list`; `turtlectl list` shows
    the whole graph), then the clients with a session open (command-line tools, scripts'
    turtlectl.Client), each as `NAME  (client: TOOL, pid PID, host HOST)`: teleop-4242 for a
    teleop of pid 4242, python-… for a script.  The one asking is not listed.  --json: one
    object, {"nodes": [...], "clients": [...]}, each row with name, pid, host, uptime, domain,
    namespace and tool ("" for a node).

    Example: turtlectl node list
    """
    from turtlectl.cli.tools import topics

    current = topics.graph(connect, domain)
    if json:
        result(format.json_value({"nodes": current.nodes, "clients": current.clients}))
        return
    lines = [n.name for n in current.nodes]
    lines += [f"{c.name}  (client: {c.tool}, pid {c.pid}, host {c.host})" for c in current.clients]
    result("\n".join(lines))


@node_app.command("info")
def node_info(
    node: str = NodeArgument,
    json: bool = JsonOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """A running node: kind, pid, host, uptime, log level, what it publishes, subscribes to and
    serves (with types), and its parameters.

    Example: turtlectl node info navigator
    """
    from turtlectl.cli.tools import introspect

    report = introspect.node_report(connect, domain, node)
    result(format.json_value(report) if json else introspect.node_text(report))


interface_app = typer.Typer(
    help="Message types: list them, show one's fields, units and defaults.\n\nExample: turtlectl interface show Twist"
)


@interface_app.command("list")
def interface_list(
    json: bool = typer.Option(False, "--json", help="One JSON array."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Every message type on the wire, with the keys that carry it (as `ros2 interface list`);
    with a system running, also every other type its nodes use (yours), with those nodes.

    Example: turtlectl interface list
    """
    from turtlectl.cli.tools import interface

    rows = interface.listing(*interface.live_types(connect, domain))
    result(format.json_value(rows) if json else interface.listing_text(rows))


@interface_app.command("show")
def interface_show(
    type_: str = typer.Argument(..., metavar="TYPE", help="A message type, e.g. Twist (any case)."),
    json: bool = JsonOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """A message type's fields: type, default, unit, range and meaning; its wire tag,
    encoding and keys (as `ros2 interface show`).  With a system running, also a type its
    nodes use (its keys from the live graph) or a Struct nested in one.

    Example: turtlectl interface show TurtleStatus
    """
    from turtlectl.cli.tools import interface

    live, keys = ({}, {}) if interface.is_builtin(type_) else interface.live_types(connect, domain)
    described = interface.description(type_, live, keys)
    result(format.json_value(described) if json else interface.description_text(described))


def view(
    turtle: str = TurtleOption,
    exit_on_loss: bool = ExitOnLossOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Draw the world live in this terminal: walls, obstacles, every turtle with its trail
    and its goal (the others named beside their arrows and the legend), the followed turtle's
    laser hits (turtle1's, or --turtle's), a legend and a status line.  A world that appears
    or changes while it runs (a simulator started, a recording played) is drawn within 2 s.
    A lost router is said on the status line and waited for; --exit-on-loss exits with code 3
    instead.  c clears the trails; q or Ctrl-C quits (exit code 0).

    Example: turtlectl view --turtle turtle2
    """
    from turtlectl.cli.tools.view import run_view  # curses: only for this command
    from turtlectl.runtime.client import services
    from turtlectl.runtime.client import session as client

    try:
        with client.client_session(connect, domain) as session:
            run_view(session, services.world(session), connect, turtle, exit_on_loss)
    except KeyboardInterrupt:
        pass


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.command("list")(list_graph)
    app.command()(view)
    app.add_typer(node_app, name="node")
    logs.register(app)
    app.add_typer(interface_app, name="interface")
