"""``turtlectl``: the command-line interface (Typer), the command surface only.

Commands parse options, call logic in cli.* that never prints (argument checks in
cli.args, launch files in cli.launchfile, sessions in cli.client, cli.services and
cli.topics, the supervisor in cli.supervisor), and print what it returns.  Logic raises
errors by meaning (cli.errors); ``main`` is the one place that prints them on stderr and
exits with their exit code.

``turtlectl --help`` must stay quick: modules that cost time to import (sessions, launch
files and node parameters, the supervisor, the curses view, the version metadata) are
imported inside the commands that use them, not here.
"""

from __future__ import annotations

import os
import shutil
import signal
import sys
from pathlib import Path
from typing import Any

import typer
import typer.core

from cli import STOPPED_BY_CTRL_C, args, lazy_module
from cli.errors import BadInput, ExitCode, Failed, Interrupted, TurtlectlError, Unreachable, exit_code
from cli.sigint import ignore_sigint, quiet_unraisable, stop_on_signals
from runtime.endpoint import CONNECT_ENV, DEFAULT_ENDPOINT, DEFAULT_PORT, DOMAIN_ENV, default_domain

format = lazy_module("cli.format")  # msgspec and the message types load when a command prints one

EXIT_CODES_HELP = """
Exit codes: 0 success, or Ctrl-C on a command that runs until stopped (echo, hz,
view, pub --rate); 1 ran but did not succeed (goal refused or not reached, an
answer that says no, a required node died); 2 bad input (arguments, launch
file); 3 nothing to talk to (no router, no navigator, no message, the router
lost); 4 could not start (port in use, log folder, a second navigator); 5 a
goal given up on (--timeout, Ctrl-C) whose cancel nobody confirmed; 130
interrupted by Ctrl-C before its result (goto, call, and the other one-shot
commands).
"""

#: the groups of `turtlectl --help`, in order, and their commands in the order listed
COMMAND_GROUPS: dict[str, tuple[str, ...]] = {
    "System": ("launch", "router", "run", "log-level", "certs"),
    "Goals and driving": ("goto", "cancel", "teleport", "reset", "teleop"),
    "Topics": ("echo", "hz", "pub", "topic"),
    "Services": ("call",),
    "Parameters": ("param",),
    "Introspection": ("list", "node", "interface", "view"),
    "Recording and Foxglove": ("record", "info", "play", "recover", "foxglove"),
}


class GroupedHelp(typer.core.TyperGroup):
    """``turtlectl --help`` lists the commands in groups (COMMAND_GROUPS), plain click
    formatting (no rich: help stays quick and greppable)."""

    def list_commands(self, ctx: Any) -> list[str]:
        ordered = [name for names in COMMAND_GROUPS.values() for name in names if name in self.commands]
        return ordered + [name for name in self.commands if name not in ordered]

    def format_commands(self, ctx: Any, formatter: Any) -> None:
        grouped = {name for names in COMMAND_GROUPS.values() for name in names}
        groups = [*COMMAND_GROUPS.items(), ("Other", tuple(n for n in self.commands if n not in grouped))]
        width = max(len(name) for name in self.commands)
        limit = formatter.width - 6 - width
        for title, names in groups:
            rows = [
                (name.ljust(width), self.commands[name].get_short_help_str(limit))
                for name in names
                if name in self.commands and not self.commands[name].hidden
            ]
            if rows:
                with formatter.section(title):
                    formatter.write_dl(rows)


app = typer.Typer(
    name="turtlectl",
    cls=GroupedHelp,
    help="A turtle robot over Zenoh, the ROS 2 way." + EXIT_CODES_HELP,
    no_args_is_help=True,
    add_completion=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,  # plain click output: usage errors stay short, help is greppable
    context_settings={"help_option_names": ["-h", "--help"]},
)

ConnectOption = typer.Option(
    DEFAULT_ENDPOINT, "--connect", envvar=CONNECT_ENV, help="Router endpoint of the system to talk to."
)


def _print_version(value: bool) -> None:
    if value:
        from cli.version import version

        typer.echo(f"turtlectl {version()}")
        raise typer.Exit(0)


def _use_domain(domain: str) -> str:
    """Check ``--domain`` and make it the domain of every session this process opens; the same
    option before or after the command (``turtlectl --domain lab1 list`` = ``turtlectl list --domain lab1``)."""
    if args.domain(domain):
        os.environ[DOMAIN_ENV] = domain  # read by every session this process opens
    return domain


DomainOption = typer.Option(
    "",
    "--domain",
    envvar=DOMAIN_ENV,
    callback=_use_domain,
    help="Keys of the system live under this prefix (two systems never mix); before or after the command.",
)


@app.callback()
def root(
    ctx: typer.Context,
    domain: str = DomainOption,
    connect: str | None = typer.Option(
        None,
        "--connect",
        help=f"Router endpoint for the client commands (default ${CONNECT_ENV}, else {DEFAULT_ENDPOINT}); "
        "launch joins it instead of running a router; before or after the command.",
    ),
    _version: bool = typer.Option(
        False, "--version", is_eager=True, callback=_print_version, help="Print turtlectl's version and exit."
    ),
) -> None:
    """A turtle robot over Zenoh, the ROS 2 way."""
    if ctx.invoked_subcommand not in STOPPED_BY_CTRL_C:
        # client commands handle Ctrl-C as KeyboardInterrupt (goto cancels, echo stops);
        # launch and router keep cli.entry's quiet handler until they install their own
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if connect is not None:  # the commands read it as their --connect default (before their own options)
        os.environ[CONNECT_ENV] = connect
        ctx.obj = {"connect": connect}  # launch joins it, as with its own --connect; router refuses it


LogLevelOption = typer.Option(
    "INFO", "--log-level", help="Least severe log line the nodes write: DEBUG, INFO, WARNING or ERROR (any case)."
)


@app.command()
def launch(
    ctx: typer.Context,
    file: Path | None = typer.Argument(
        None, metavar="FILE", help="Launch file (default: ./launch.toml, else the packaged one)."
    ),
    port: int = typer.Option(DEFAULT_PORT, "--port", min=1, max=65535, help="Router port."),
    listen: str = typer.Option("127.0.0.1", "--listen", help="Address the router listens on (other hosts: theirs)."),
    join: str | None = typer.Option(None, "--connect", help="Run no router: join the one at this endpoint."),
    only: list[str] = typer.Option([], "--only", help="Run only this node (repeatable)."),
    exclude: list[str] = typer.Option([], "--exclude", help="Do not run this node (repeatable)."),
    set_: list[str] = typer.Option(
        [],
        "--set",
        help="NODE.PARAM=VALUE or world/limits/supervisor.KEY=VALUE override (repeatable), validated like the file.",
    ),
    check: bool = typer.Option(False, "--check", help="Validate the file (and overrides), print the plan, and exit."),
    persist: bool = typer.Option(
        False, "--persist", help="A node started again (respawn) keeps parameters changed by `param set`."
    ),
    secure: bool = typer.Option(
        False, "--secure", help="Only sessions that log in join: a new login per node and for local clients."
    ),
    insecure: bool = typer.Option(
        False, "--insecure", help="Listen beyond loopback without logins (anyone who reaches it can drive)."
    ),
    tls: Path | None = typer.Option(
        None, "--tls", metavar="DIR", help="With --secure: mutual TLS with the certificates of `turtlectl certs DIR`."
    ),
    log_level: str = LogLevelOption,
    log_dir: Path | None = typer.Option(
        None, "--log-dir", envvar="TURTLECTL_LOG_DIR", help="Parent folder of run folders (default ~/.turtlectl/log)."
    ),
    domain: str = DomainOption,
) -> None:
    """Start the router and every node of a launch file; Ctrl-C stops them all.

    Each node's output is prefixed with its name and also written to <log-dir>/<run>/<node>.log.

    Example: turtlectl launch --port 7448 --set navigator.goal_timeout=60
    """
    from cli.launchfile import default_launch_file, launch_plan
    from cli.supervisor import logs
    from cli.supervisor.manager import Supervisor
    from cli.supervisor.printer import Printer

    if join is None:  # `turtlectl --connect E launch` joins E, as `turtlectl launch --connect E`
        join = (ctx.obj or {}).get("connect")
    level = args.log_level(log_level)
    host = args.listen_address(listen)
    args.exposure(host, secure, insecure, joins=join is not None, tls=tls is not None)
    if tls is not None:
        args.tls_folder(tls)
    plan = launch_plan(file or default_launch_file(), only, exclude, set_)
    if check:
        typer.echo(format.plan_text(plan))
        return
    connect = args.endpoint(join) if join is not None else ""
    printer = Printer([e.name for e in plan.launch.node])
    supervisor = Supervisor(
        plan,
        printer,
        None if join else port,
        connect,
        default_domain(),
        host,
        log_dir or logs.default_parent(),
        persist=persist,
        log_level=level,
        secure=secure,
        tls=tls,
    )
    try:
        code = supervisor.run()
    finally:
        printer.close()
    raise typer.Exit(code)


@app.command()
def certs(
    folder: Path = typer.Argument(
        ..., metavar="DIR", help="Folder to write them into (made if missing; never overwritten)."
    ),
    host: list[str] = typer.Option([], "--host", help="A name or address the router is reached by (repeatable)."),
) -> None:
    """Make a certificate authority and the router's and clients' certificates for
    `launch --secure --tls DIR` (mutual TLS); the keys are readable by you only.  Another
    machine that joins copies ca.pem, client.pem and client.key and sets TURTLECTL_TLS.

    Example: turtlectl certs ~/.turtlectl/tls --host 192.168.1.20
    """
    from cli.certs import make

    written = make(folder, host)
    _result("wrote " + ", ".join(str(p) for p in written))


@app.command()
def router(
    ctx: typer.Context,
    port: int = typer.Option(DEFAULT_PORT, "--port", min=1, max=65535, help="Port to listen on."),
    listen: str = typer.Option("127.0.0.1", "--listen", help="Address to listen on (loopback by default)."),
    insecure: bool = typer.Option(
        False, "--insecure", help="Listen beyond loopback without logins (anyone who reaches it can drive)."
    ),
) -> None:
    """Run a Zenoh router alone, for nodes started with `launch --connect` (as rmw_zenohd).

    Example: turtlectl router --port 7447
    """
    from cli.supervisor.router import run_router

    if (ctx.obj or {}).get("connect") is not None:
        raise BadInput("router takes no --connect: it is the router the others connect to (see --port, --listen)")
    host = args.listen_address(listen)
    args.exposure(host, secure=False, insecure=insecure, can_secure=False)
    run_router(port, host, lambda: typer.echo(f"router listening on tcp/{host}:{port}; Ctrl-C stops it", err=False))


def _result(text: str) -> None:
    """Print a one-shot command's result: from now on a Ctrl-C changes nothing (no 130, no
    traceback from Zenoh's threads while the process ends)."""
    ignore_sigint()
    typer.echo(text)


@app.command(context_settings={"ignore_unknown_options": True})
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
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Send the turtle to (X, Y) facing THETA degrees and wait for the outcome.

    On a terminal a live progress line shows the goal's state; piped, only the
    outcome is printed.  Ctrl-C or --timeout cancels the goal (exit code 130 or 1), and
    exit code 5 says that nobody confirmed the cancel: the turtle may still be driving.

    Example: turtlectl goto 8 5 90
    """
    from cli import services
    from messages import NavigateToFeedback, NavigateToRequest

    request = NavigateToRequest(
        x=args.finite_number(x, "x"), y=args.finite_number(y, "y"), theta=args.finite_number(theta, "theta")
    )
    live = sys.stdout.isatty() and not json

    def show(fb: NavigateToFeedback) -> None:  # the terminal's width now: it may be resized meanwhile
        typer.echo("\r\033[K" + format.progress_line(fb, shutil.get_terminal_size().columns), nl=False)

    try:
        response, _ = services.navigate(
            connect, request, timeout if timeout is not None else services.NO_LIMIT, show if live else None
        )
    except KeyboardInterrupt:  # before the goal was sent (one running is canceled and checked in navigate)
        raise Interrupted("interrupted") from None
    finally:
        if live:
            typer.echo("\r\033[K", nl=False)
    _result(format.message_json(response) if json else format.outcome_line(response))
    raise typer.Exit(ExitCode.OK if response.success else ExitCode.FAILED)


@app.command()
def cancel(connect: str = ConnectOption, domain: str = DomainOption) -> None:
    """Cancel the running goal: the turtle brakes at once; its caller gets reason "canceled".

    Exit code 1 if no goal was running.

    Example: turtlectl cancel
    """
    from cli import services
    from messages import Cancel, keys

    (ack,) = services.simple_call(connect, keys.CANCEL, Cancel())
    _result(ack.detail)
    raise typer.Exit(ExitCode.OK if ack.ok else ExitCode.FAILED)


@app.command(context_settings={"ignore_unknown_options": True})
def teleport(
    x: str = typer.Argument(..., metavar="X", help="x, m."),
    y: str = typer.Argument(..., metavar="Y", help="y, m."),
    theta: str = typer.Argument(..., metavar="THETA", help="Heading, degrees (as for goto)."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Put the turtle at (X, Y) facing THETA degrees, at rest (turtlesim's teleport_absolute).

    Example: turtlectl teleport 2 2 45
    """
    from cli import services
    from messages import TeleportAbsolute, keys
    from messages.angles import heading_radians

    degrees = args.finite_number(theta, "theta")
    request = TeleportAbsolute(
        x=args.finite_number(x, "x"), y=args.finite_number(y, "y"), theta=heading_radians(degrees)
    )
    acks = services.simple_call(connect, keys.TELEPORT, request)
    if not all(a.ok for a in acks):  # the simulator's own words (they are in radians, as its request)
        raise Failed(format.ack_lines(acks))
    _result(format.teleport_line(request.x, request.y, degrees))


@app.command()
def reset(connect: str = ConnectOption, domain: str = DomainOption) -> None:
    """Put the turtle back at its spawn pose and fill the battery (turtlesim's reset).

    Example: turtlectl reset
    """
    from cli import services
    from messages import Reset, keys

    acks = services.simple_call(connect, keys.RESET, Reset(), everyone=True)
    _result(format.ack_lines(acks))
    raise typer.Exit(ExitCode.OK if all(a.ok for a in acks) else ExitCode.FAILED)


@app.command()
def echo(
    topic: str = typer.Argument(..., metavar="TOPIC", help="Key expression, e.g. robot/status or turtle1/*."),
    once: bool = typer.Option(False, "--once", help="Print one message and exit."),
    count: int | None = typer.Option(None, "--count", min=1, help="Exit after N messages."),
    json: bool = typer.Option(False, "--json", help="One JSON object per line."),
    csv: bool = typer.Option(False, "--csv", help="CSV: a header line, then one line per message."),
    field: list[str] = typer.Option(
        [],
        "--field",
        help="Print only this field (dotted path, e.g. ranges.0); repeat it for several, one line per message.",
    ),
    full: bool = typer.Option(False, "--full", help="Print long arrays whole."),
    timeout: float | None = typer.Option(None, "--timeout", min=0.1, help="Exit after S seconds."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Print the messages published on TOPIC, decoded whatever their type.

    Keeps printing across a publisher's restart; runs until Ctrl-C (exit code 0), --count or
    --timeout.  When nothing arrives for 3 s (from the start, or after messages flowed) it says
    why on stderr, once per silence; the router lost is exit code 3.  With a wildcard each
    message names its key.  Example: turtlectl echo robot/status --field battery
    """
    from cli import topics

    args.one_format(json, csv)
    limit = args.echo_limit(once, count)
    header = False
    wildcard = "*" in topic
    fields = list(dict.fromkeys(field))  # each once, in the order typed
    try:
        for item in topics.stream(connect, topic, limit, timeout):
            if isinstance(item, topics.Silence):
                typer.echo(item.text, err=True)
                continue
            if item.message is None:
                typer.echo(f"skipped a message on {item.key}: {item.problem}", err=True)
                continue
            msg = item.message
            if fields:
                values = {path: format.select_field(msg, path) for path in fields}
                if csv and not header:
                    typer.echo(format.fields_header(fields))
                    header = True
                typer.echo(format.fields_line(values, json, csv, full))
            elif json:
                typer.echo(format.message_json(msg, item.key if wildcard else None))
            elif csv:
                if not header:
                    typer.echo(format.csv_header(msg))
                    header = True
                typer.echo(format.csv_row(msg))
            else:
                typer.echo(format.message_block(msg, full, item.key if wildcard else None))
    except KeyboardInterrupt:
        pass
    except BrokenPipeError:  # `| head`: the reader has what it wanted
        sys.stderr.close()


@app.command("list")
def list_graph(
    json: bool = typer.Option(False, "--json", help="The graph as one JSON object."),
    all_: bool = typer.Option(False, "--all", help="Also each node's own services (parameters, node info, log level)."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """The live graph: nodes (name, pid, host, uptime), topics with their publishers and
    subscribers, and services; read from liveliness tokens now, never from a cache.
    Without --domain, systems running in domains are listed too, their names and keys
    prefixed with the domain (lab1/sim, lab1/robot/status).  The services every node has
    (turtlectl/params/<node>, turtlectl/nodes/<node>, ...) are counted, not listed, unless --all.

    Example: turtlectl list
    """
    from cli import topics
    from cli.graph import graph_text, without_node_services

    current = topics.graph(connect)
    if not all_:
        current = without_node_services(current)
    _result(format.json_value(current) if json else graph_text(current))


def _use_node(text: str | None) -> str | None:
    """NODE checked; ``lab1/navigator`` (as `list` shows a node of domain lab1 to a client without
    --domain) makes lab1 the domain of this command."""
    if text is None:
        return None
    in_domain, name = args.node_name(text)
    if in_domain:
        chosen = os.environ.get(DOMAIN_ENV, "")
        if chosen and chosen != in_domain:
            raise BadInput(f"node {text!r} is in domain {in_domain!r}, not in --domain {chosen!r}")
        os.environ[DOMAIN_ENV] = in_domain
    return name


NodeArgument = typer.Argument(
    ...,
    metavar="NODE",
    callback=_use_node,
    help="A node's name, as `turtlectl list` shows it (lab1/sim: in domain lab1).",
)
param_app = typer.Typer(
    help="A running node's parameters: list, get, set, describe, dump (as `ros2 param`).\n\n"
    "Example: turtlectl param set navigator goal_timeout 60"
)
app.add_typer(param_app, name="param")
ParamArgument = typer.Argument(..., metavar="NAME", help="A parameter, e.g. goal_timeout or gains.lookahead.")


@param_app.command("list")
def param_list(
    node: str | None = typer.Argument(
        None, metavar="[NODE]", callback=_use_node, help="A node's name (default: every running node)."
    ),
    json: bool = typer.Option(False, "--json", help="One JSON array of names (by node without NODE)."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """The names of a running node's parameters (a table's entries dotted: gains.lookahead),
    or of every node's.

    Example: turtlectl param list navigator
    """
    from cli import params

    if node is None:
        by_node = params.listing_all(connect)
        _result(format.json_value(by_node) if json else params.listing_text(by_node))
        return
    names = params.names(params.fetch(connect, node))
    _result(format.json_value(names) if json else "\n".join(names))


@param_app.command("set", context_settings={"ignore_unknown_options": True})  # negative VALUEs
def param_set(
    node: str = NodeArgument,
    name: str = ParamArgument,
    value: str = typer.Argument(
        ..., metavar="VALUE", help='A TOML value as in a launch file: 60, 0.5, true, [1, 2], "text".'
    ),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Change a parameter of a running node at once, validated as the launch file is (same
    errors, exit 2; a node of your own kind: as it describes its parameters, and by the node);
    parameters that cannot change at run time are refused with the reason.
    The node publishes a ParameterEvent (`turtlectl echo turtlectl/parameter_events`).  A node
    that is started again (respawn) runs with the launch file's value unless the system was
    launched with --persist.

    Example: turtlectl param set navigator goal_timeout 60
    """
    from cli import params

    _result(params.set_value(connect, node, name, value))


@param_app.command("describe")
def param_describe(
    node: str = NodeArgument,
    name: str = ParamArgument,
    json: bool = typer.Option(False, "--json", help="One JSON object."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """A parameter's type, unit, range, default, meaning, value now, and whether it can change
    at run time.

    Example: turtlectl param describe navigator goal_timeout
    """
    from cli import params

    info, now = params.describe(connect, node, name)
    if json:
        _result(format.json_value({**params.plain(info), "value": now}))
    else:
        _result(params.describe_text(node, info, now))


@param_app.command("get")
def param_get(
    node: str = NodeArgument,
    name: str = ParamArgument,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """One parameter's value as the node runs with it, in JSON.

    Example: turtlectl param get navigator goal_timeout
    """
    from cli import params

    _result(format.json_value(params.value(params.fetch(connect, node), node, name)))


@param_app.command("dump")
def param_dump(
    node: str = NodeArgument,
    json: bool = typer.Option(False, "--json", help="One JSON object instead of TOML."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Every parameter of a running node, as TOML for its [node.params] table in a launch file.

    Example: turtlectl param dump navigator > navigator.toml
    """
    from cli import params

    values = params.fetch(connect, node)
    _result(format.json_value(values) if json else params.dump(node, values))


node_app = typer.Typer(help="Running nodes in detail (as `ros2 node`).\n\nExample: turtlectl node info navigator")
app.add_typer(node_app, name="node")


@node_app.command("info")
def node_info(
    node: str = NodeArgument,
    json: bool = typer.Option(False, "--json", help="One JSON object."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """A running node: kind, pid, host, uptime, log level, what it publishes, subscribes to and
    serves (with types), and its parameters.

    Example: turtlectl node info navigator
    """
    from cli import introspect

    report = introspect.node_report(connect, node)
    _result(format.json_value(report) if json else introspect.node_text(report))


topic_app = typer.Typer(
    help="One topic in detail (as `ros2 topic info`); echo, hz and pub are commands of their own.\n\n"
    "Example: turtlectl topic info turtle1/pose -v"
)
app.add_typer(topic_app, name="topic")


@topic_app.command("info")
def topic_info(
    key: str = typer.Argument(..., metavar="KEY", help="A topic's key, e.g. turtle1/pose."),
    verbose: bool = typer.Option(False, "-v", "--verbose", help="Also measure its rate over a second."),
    json: bool = typer.Option(False, "--json", help="One JSON object."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """A topic's type, and its publishers and subscribers with their nodes (pid, host); with
    -v, its rate measured over one second.

    Example: turtlectl topic info turtle1/pose -v
    """
    from cli import introspect

    report = introspect.topic_report(connect, key, verbose)
    _result(format.json_value(report) if json else introspect.topic_text(report))


@app.command("log-level")
def log_level_command(
    node: str = NodeArgument,
    level: str = typer.Argument(..., metavar="LEVEL", help="DEBUG, INFO, WARNING (or WARN) or ERROR, any case."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Change a running node's log level at once (`launch --log-level` sets it for all at start).

    Example: turtlectl log-level navigator DEBUG
    """
    from cli import introspect

    _result(introspect.set_log_level(connect, node, level))


interface_app = typer.Typer(
    help="Message types: list them, show one's fields, units and defaults.\n\nExample: turtlectl interface show Twist"
)
app.add_typer(interface_app, name="interface")


@interface_app.command("list")
def interface_list(json: bool = typer.Option(False, "--json", help="One JSON array.")) -> None:
    """Every message type on the wire, with the keys that carry it (as `ros2 interface list`).

    Example: turtlectl interface list
    """
    from cli import interface

    rows = interface.listing()
    _result(format.json_value(rows) if json else interface.listing_text(rows))


@interface_app.command("show")
def interface_show(
    type_: str = typer.Argument(..., metavar="TYPE", help="A message type, e.g. Twist (any case)."),
    json: bool = typer.Option(False, "--json", help="One JSON object."),
) -> None:
    """A message type's fields: type, default, unit, range and meaning; its wire tag,
    encoding and keys (as `ros2 interface show`).

    Example: turtlectl interface show TurtleStatus
    """
    from cli import interface

    described = interface.description(type_)
    _result(format.json_value(described) if json else interface.description_text(described))


@app.command()
def hz(
    names: list[str] = typer.Argument(..., metavar="TOPIC...", help="One or more key expressions."),
    window: int = typer.Option(100, "--window", min=2, help="At most N messages (of the last 5 s) per statistic."),
    duration: float | None = typer.Option(None, "--duration", min=0.5, help="Stop after S seconds."),
    json: bool = typer.Option(False, "--json", help="JSON lines."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Rate of each TOPIC from arrival times (with jitter), and the publisher's own rate from stamps.

    Each second, a line for each TOPIC that had messages since the last one, over the messages
    of the last 5 s; a topic silent for 3 s (from the start, or after it stopped) is reported with
    the reason, once per silence; the router lost is exit code 3.  Runs until Ctrl-C (exit code
    0) or --duration.  Example: turtlectl hz robot/status obstacles --duration 10
    """
    from cli import topics
    from cli.rates import rate_line

    printed = False
    try:
        for stats in topics.measure_rates(connect, names, window, duration):
            if isinstance(stats, topics.Silence):
                typer.echo(stats.text, err=True)
                continue
            printed = printed or bool(stats)
            for st in stats:
                typer.echo(format.json_value(st) if json else rate_line(st))
    except KeyboardInterrupt:
        pass
    if duration is not None and not printed:
        raise Unreachable(f"no messages on {', '.join(names)} within {duration:g} s")


@app.command()
def pub(
    topic: str = typer.Argument(..., metavar="TOPIC", help="Key to publish on."),
    message: str = typer.Argument(..., metavar="JSON", help="The message's fields as JSON."),
    rate: float | None = typer.Option(None, "--rate", min=0.01, help="Publish at HZ until Ctrl-C (or --times)."),
    once: bool = typer.Option(False, "--once", help="Publish once (the default without --rate)."),
    times: int | None = typer.Option(None, "--times", min=1, help="Publish N times."),
    type_name: str | None = typer.Option(None, "--type", help="Message type, for keys without a known one."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Publish a message built from JSON, validated for the topic's type before anything is sent
    (a known topic's own type: --type cannot change it).

    With --rate and no --times it runs until Ctrl-C (exit code 0); otherwise Ctrl-C before
    the last message is exit code 130.
    Example: turtlectl pub turtle1/cmd_vel '{"linear": 1.0, "angular": 0.5}' --rate 10
    """
    from cli import build, client, topics

    key = client.check_key(topic, publish=True)
    msg = build.topic_message(client.base_key(key), message, type_name)
    count = args.publish_count(once, rate, times)
    try:
        sent = topics.publish(connect, topic, msg, rate if rate is not None else 10.0, count)
    except KeyboardInterrupt:
        if count is not None:
            raise Interrupted("interrupted before every message was sent") from None
        return
    typer.echo(f"published {sent} {type(msg).__name__} on {key}", err=True)


@app.command()
def call(
    service: str = typer.Argument(..., metavar="SERVICE", help="Key of the queryable."),
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
    from cli import build, client, services
    from messages import NavigateToFeedback

    key = client.check_key(service)
    body = build.service_request(client.base_key(key), request, type_name)

    def show(reply: Any) -> None:
        if isinstance(reply, services.Raw):
            typer.echo(reply.payload.decode("utf-8", "replace"))
        else:
            typer.echo(format.message_json(reply) if json else format.message_block(reply))

    code = ExitCode.OK
    try:  # a goal's feedback is shown from inside the call: a Ctrl-C there cancels the goal and checks
        for reply in services.call_service(connect, key, body, timeout, on_feedback=show):
            if not isinstance(reply, NavigateToFeedback):  # an answer: a Ctrl-C from now on changes nothing
                ignore_sigint()
            show(reply)
            if not isinstance(reply, services.Raw):
                code = max(code, services.reply_code(reply))
    except KeyboardInterrupt:
        raise Interrupted("interrupted") from None
    raise typer.Exit(code)


@app.command()
def run(
    node: str = typer.Argument(..., metavar="NODE", help="Name of a node in the launch file."),
    param: list[str] = typer.Option([], "--param", "-p", help="KEY=VALUE override (repeatable; a.b=1 for tables)."),
    file: Path | None = typer.Option(None, "--file", help="Launch file (default as for launch)."),
    log_level: str = LogLevelOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Run one node in the foreground with the parameters the launch file gives it (and
    overrides), joining the system at --connect: for debugging, or on another machine.

    Example: turtlectl run navigator -p goal_timeout=60 --log-level DEBUG
    """
    from cli.launchfile import default_launch_file, load_launch, node_config
    from cli.supervisor.process import exec_node

    level = args.log_level(log_level)
    path = file or default_launch_file()
    exec_node(node_config(load_launch(path), node, args.endpoint(connect), param, default_domain(), level))


@app.command()
def view(connect: str = ConnectOption, domain: str = DomainOption) -> None:
    """Draw the world live in this terminal: walls, obstacles, the turtle and its trail,
    the goal, the laser hits, a legend and a status line.  c clears the trail; q or Ctrl-C
    quits (exit code 0).

    Example: turtlectl view
    """
    from cli import client, services
    from cli.view import run_view  # curses: only for this command

    try:
        with client.client_session(connect) as session:
            run_view(session, services.world(session), connect)
    except KeyboardInterrupt:
        pass


@app.command()
def teleop(
    linear: float = typer.Option(2.0, "--linear", min=0.0, help="Speed of up/down (w/s), m/s."),
    angular: float = typer.Option(2.0, "--angular", min=0.0, help="Turn rate of left/right (a/d), rad/s."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Drive the turtle from the keyboard, as turtlesim's teleop_turtle_key: arrow keys or
    w/a/s/d (a held key keeps the turtle going; it stops 0.7 s after the key is released),
    space stops (and cancels a running goal), q or Ctrl-C quits (exit code 0).  A goal
    running when the keys start driving is canceled (reason "teleop").  The status line
    shows the command being sent and the turtle's pose.  Its input must be a terminal
    (exit code 2 otherwise).

    Example: turtlectl teleop --linear 1.0
    """
    from cli import client
    from cli.teleop import run_teleop, terminal_fd

    args.finite_option(linear, "--linear")
    args.finite_option(angular, "--angular")
    fd = terminal_fd(sys.stdin)
    with client.client_session(connect) as session:
        run_teleop(session, linear, angular, connect, fd, sys.stdout)


@app.command()
def record(
    topics: list[str] = typer.Argument(
        None, metavar="[TOPIC]...", help="Key expressions to record, e.g. robot/status turtle1/*."
    ),
    all_topics: bool = typer.Option(False, "-a", "--all", help="Record every topic (streams and feedback)."),
    output: Path | None = typer.Option(
        None, "-o", "--output", help="The MCAP file to write (must not exist).  [default: turtlectl_<date>-<time>.mcap]"
    ),
    duration: float | None = typer.Option(None, "--duration", min=0.1, help="Stop after S seconds."),
    exclude: list[str] = typer.Option(
        [], "--exclude", metavar="KEY_EXPR", help="Leave out keys matching this (repeatable)."
    ),
    scene: bool = typer.Option(
        False, "--scene", help="Also record the Foxglove 3D scene (as `turtlectl foxglove` draws it)."
    ),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Record topics into an MCAP file that Foxglove opens, as `ros2 bag record`.

    Each message keeps its receive time, its own stamp, its key and its type.  Ctrl-C or
    SIGTERM finishes the file; if the recorder is killed, at most the last second is lost.

    Example: turtlectl record -a -o run.mcap
    """
    from cli import record as recording
    from cli.bag import refuse_existing
    from cli.version import version

    args.finite_option(duration, "--duration")
    keys, excluded = recording.keys_to_record(topics or [], all_topics, exclude)
    path = output or recording.default_path()
    refuse_existing(path)
    with stop_on_signals() as stop:
        live = sys.stderr.isatty()
        typer.echo(
            f"recording {', '.join(keys)} into {path}" + (f" (not {', '.join(excluded)})" if excluded else ""), err=True
        )
        last = None
        for last in recording.record(connect, keys, excluded, path, duration, stop, f"turtlectl {version()}", scene):
            if live and not last.done:
                typer.echo(
                    "\r\033[K" + format.recording_line(last.elapsed, last.messages, last.size), nl=False, err=True
                )
        if live:
            typer.echo("\r\033[K", nl=False, err=True)
    if last is not None:
        _result(
            f"recorded {last.messages} messages in {last.elapsed:.1f} s into {path} ({format.size_text(last.size)})"
        )


@app.command()
def info(
    file: Path = typer.Argument(..., metavar="FILE", help="A recording (MCAP file)."),
    json: bool = typer.Option(False, "--json", help="One JSON object."),
) -> None:
    """What a recording holds, as `ros2 bag info`: size, duration, start and end, messages per
    topic with type, rate and encoding, and whether the recorder closed the file.

    Example: turtlectl info run.mcap
    """
    from cli.bag import Recording

    details = Recording(file).info()
    _result(format.info_json(details) if json else format.info_text(details))


@app.command()
def play(
    file: Path = typer.Argument(..., metavar="FILE", help="A recording (MCAP file)."),
    rate: float = typer.Option(1.0, "--rate", min=0.01, help="Speed factor (2 = twice as fast)."),
    loop: bool = typer.Option(False, "--loop", help="Play again and again until Ctrl-C."),
    start_offset: float = typer.Option(0.0, "--start-offset", min=0.0, help="Start S seconds into the recording."),
    topics: list[str] = typer.Option([], "--topics", metavar="KEY", help="Play only this key (repeatable)."),
    remap: list[str] = typer.Option(
        [], "--remap", metavar="OLD:=NEW", help="Publish OLD's messages on NEW (repeatable)."
    ),
    keep_stamps: bool = typer.Option(
        False, "--keep-stamps", help="Keep the recorded stamps (default: stamp when sent)."
    ),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Publish a recording again, each message at its recorded time (divided by --rate), as
    `ros2 bag play`.  On a terminal, space pauses and resumes; Ctrl-C stops (exit code 0).

    Example: turtlectl play run.mcap --rate 2
    """
    from cli import play as player
    from cli.bag import Recording

    args.finite_option(rate, "--rate")
    args.finite_option(start_offset, "--start-offset")
    remaps = player.parse_remaps(remap)
    keys = [client_key(t) for t in topics] or None
    recording = Recording(file)
    if not recording.closed:
        from cli.recover import hint

        typer.echo(
            f"warning: {file} was not closed (the recorder was killed?): playing what is complete; {hint(file)}",
            err=True,
        )
    with stop_on_signals() as stop:
        live = sys.stdin.isatty() and sys.stderr.isatty()
        played = 0
        shown = ""
        with player.space_toggles(live) as paused:
            for item in player.play(
                connect, recording, rate, start_offset, keys, remaps, keep_stamps, loop, paused, stop.is_set
            ):
                played += not item.paused
                state = "paused" if item.paused else "playing"
                if live and (state != shown or item.index % 25 == 0 or item.index + 1 == item.total):
                    shown = state
                    typer.echo(
                        f"\r\033[K{state} {item.offset:8.2f} s  {item.index + 1}/{item.total}"
                        + (f"  loop {item.loop + 1}" if loop else "")
                        + "  (space: pause)",
                        nl=False,
                        err=True,
                    )
        if live:
            typer.echo("\r\033[K", nl=False, err=True)
    _result(f"played {played} messages from {file}")


@app.command()
def recover(
    file: Path = typer.Argument(..., metavar="FILE", help="A recording the recorder did not finish (MCAP file)."),
    output: Path | None = typer.Option(
        None, "-o", "--output", help="The file to write (must not exist).  [default: FILE-recovered.mcap]"
    ),
) -> None:
    """Write a complete, indexed copy of a recording that was not closed (the recorder was
    killed), as `mcap recover` and `ros2 bag reindex`: everything readable is kept, the file
    itself is left as it is.

    Example: turtlectl recover run.mcap   (writes run-recovered.mcap)
    """
    from cli.recover import recover as recover_file
    from cli.recover import text

    _result(text(recover_file(file, output)))


@app.command()
def foxglove(
    port: int = typer.Option(8765, "--port", min=0, max=65535, help="WebSocket port (0: any free one)."),
    host: str = typer.Option("127.0.0.1", "--host", help="Address to listen on (loopback by default)."),
    layout: Path | None = typer.Option(None, "--layout", help="Write the Foxglove layout file here and exit."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Serve the running system to the Foxglove app (open the printed URL, or connect the app
    to ws://HOST:PORT): every topic, a ready-made 3D scene (world, obstacles, turtle, trail,
    scan, goal), and navigate_to, cancel, reset and teleport as services.

    Example: turtlectl foxglove   (then in Foxglove: Open connection, ws://127.0.0.1:8765)
    """
    from importlib import resources

    if layout is not None:
        text = resources.files("cli").joinpath("foxglove_layout.json").read_text()
        try:
            layout.write_text(text)
        except OSError as exc:
            raise BadInput(f"cannot write {layout}: {exc.strerror or exc}") from None
        _result(f"wrote {layout}: in Foxglove, Layouts > Import from file")
        return
    import ipaddress

    try:
        address = str(ipaddress.ip_address(host))
    except ValueError:
        raise BadInput(f"--host {host!r} is not an IP address (e.g. 127.0.0.1)") from None
    from cli import bridge

    with stop_on_signals() as stop:

        def started(server) -> None:
            where = f"ws://{address}:{server.port}"
            typer.echo(f"serving Foxglove on {where}; open {server.app_url()} or connect the app to {where}", err=True)
            if not ipaddress.ip_address(address).is_loopback:
                typer.echo(
                    f"warning: anyone who can reach {address}:{server.port} sees the robot and can send it goals",
                    err=True,
                )

        for _ in bridge.serve(connect, address, port, stop, started):
            pass


def client_key(text: str) -> str:
    from cli.client import check_key

    return check_key(text, publish=True)


def error_line(error: TurtlectlError) -> str:
    """What the user reads on stderr for ``error`` (a Ctrl-C is no error: its message says what happened)."""
    return f"turtlectl: {error.message}" if isinstance(error, Interrupted) else f"turtlectl: error: {error.message}"


def main() -> None:
    """Console entry point: run the app; the one place where an error becomes its message on
    stderr and its exit code (cli.errors.exit_code)."""
    sys.unraisablehook = quiet_unraisable
    try:
        app()
    except SystemExit:
        # the result is out (click ends every command with SystemExit): a late Ctrl-C must
        # not turn it into 130, nor hit Zenoh's threads while the interpreter shuts down
        ignore_sigint()
        raise
    except TurtlectlError as exc:
        typer.echo(error_line(exc), err=True)
        sys.exit(int(exit_code(exc)))
    except KeyboardInterrupt:
        typer.echo("turtlectl: interrupted", err=True)
        sys.exit(int(ExitCode.INTERRUPTED))


if __name__ == "__main__":
    main()
