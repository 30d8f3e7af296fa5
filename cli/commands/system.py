"""turtlectl's System commands: launch, router, run, log-level, certs.

The launch side's logic lives in cli.system (launch files, the supervisor, certificates);
it is imported inside each command, so that ``--help`` does not pay for it."""

from __future__ import annotations

from pathlib import Path

import typer

from turtlectl.cli import args
from turtlectl.cli.commands.options import (
    ConnectOption,
    DomainOption,
    LogLevelOption,
    NodesArgument,
    format,
    result,
)
from turtlectl.runtime.client import checks
from turtlectl.runtime.client.errors import BadInput
from turtlectl.runtime.endpoint import DEFAULT_PORT, LOG_DIR_ENV


def launch(
    ctx: typer.Context,
    file: Path | None = typer.Argument(
        None, metavar="FILE", help="Launch file (default: ./launch.toml, else the packaged one)."
    ),
    port: int = typer.Option(DEFAULT_PORT, "--port", min=1, max=65535, help="Router port."),
    listen: str = typer.Option(
        "127.0.0.1",
        "--listen",
        help="Address the router listens on, loopback as well (this host's tools need no --connect; other hosts: ADDRESS).",
    ),
    join: str | None = typer.Option(None, "--connect", help="Run no router: join the one at this endpoint."),
    only: list[str] = typer.Option(
        [],
        "--only",
        help="Run only this node, the nodes of a turtle or namespace (turtle1, turtle2) or of a glob "
        "('turtle2/*'), e.g. on another host (repeatable).",
    ),
    exclude: list[str] = typer.Option(
        [],
        "--exclude",
        help="Do not run this node, nor the nodes of a turtle, namespace or glob, as --only names them (repeatable).",
    ),
    set_: list[str] = typer.Option(
        [],
        "--set",
        help="NODE.PARAM=VALUE or world/limits/supervisor.KEY=VALUE override (repeatable), validated like the file.",
    ),
    arg: list[str] = typer.Option(
        [],
        "--arg",
        metavar="NAME=VALUE",
        help="A launch argument, NAME an [arg.NAME] of FILE: --arg speed=2 (or speed:=2); one --arg each, repeatable; --check lists them.",
    ),
    check: bool = typer.Option(
        False, "--check", help="Validate the file (and overrides), print the plan and its arguments, and exit."
    ),
    time_scale: float | None = typer.Option(
        None,
        "--time-scale",
        min=0.1,
        max=20.0,
        metavar="F",
        help="Simulated time, F times as fast as the wall clock: the simulator's real_time_factor, and every node on its clock (use_sim_time).",
    ),
    use_sim_time: bool = typer.Option(
        False,
        "--use-sim-time",
        help="Every node on simulated time (the clock key): the simulator's, or a replay's (`play --clock`) without one.",
    ),
    web: int | None = typer.Option(
        None,
        "--web",
        min=1,
        max=65535,
        metavar="PORT",
        help="Also serve the web page (turtlectl web) on 127.0.0.1:PORT, unless the file runs one.",
    ),
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
    deny_host: list[str] = typer.Option(
        [],
        "--deny-host",
        metavar="NAME",
        help="With --tls: shut out the host whose certificate `certs DIR --issue NAME` made (repeatable).",
    ),
    log_level: str = LogLevelOption,
    log_dir: Path | None = typer.Option(
        None, "--log-dir", envvar=LOG_DIR_ENV, help="Parent folder of run folders (default ~/.turtlectl/log)."
    ),
    domain: str = DomainOption,
) -> None:
    """Start the router and every node of a launch file; Ctrl-C stops them all.

    Each node's output is prefixed with its name and also written to <log-dir>/<run>/<node>.log.

    Example: turtlectl launch --port 7448 --set navigator.goal_timeout=60
    """
    from turtlectl.cli.system.launchfile import default_launch_file
    from turtlectl.cli.system.overrides import launch_plan
    from turtlectl.cli.system.report import positional_arg_problem
    from turtlectl.cli.system.supervisor import logs
    from turtlectl.cli.system.supervisor.manager import Supervisor
    from turtlectl.cli.system.supervisor.printer import Printer

    why = positional_arg_problem(file, ctx.args)
    if why:
        raise BadInput(why)
    if join is None:  # `turtlectl --connect E launch` joins E, as `turtlectl launch --connect E`
        join = (ctx.obj or {}).get("connect")
    level = args.log_level(log_level)
    host = args.listen_address(listen)
    args.exposure(host, secure, insecure, joins=join is not None, tls=tls is not None)
    if tls is not None:
        args.tls_folder(tls)
    if deny_host:
        from turtlectl.cli.system.certs import allowed_common_names

        if tls is None:
            raise BadInput("--deny-host tells hosts apart by their certificates: give it with --secure --tls DIR")
        allowed_common_names(tls, deny_host)  # BadInput for a host no certificate was issued to
    plan = launch_plan(
        file or default_launch_file(),
        only,
        exclude,
        set_,
        time_scale,
        arguments=arg,
        use_sim_time=use_sim_time,
        web=web,
    )
    if check:
        typer.echo(format.plan_text(plan))
        return
    connect = checks.endpoint(join) if join is not None else ""
    printer = Printer([e.name for e in plan.launch.node])
    for note in format.plan_notes(plan):
        printer.system(f"note: {note}")
    supervisor = Supervisor(
        plan,
        printer,
        None if join else port,
        connect,
        domain,
        host,
        log_dir or logs.default_parent(),
        persist=persist,
        log_level=level,
        secure=secure,
        tls=tls,
        deny_hosts=tuple(deny_host),
    )
    try:
        code = supervisor.run()
    finally:
        printer.close()
    raise typer.Exit(code)


def certs(
    folder: Path = typer.Argument(
        ..., metavar="DIR", help="Folder to write them into (made if missing; never overwritten)."
    ),
    host: list[str] = typer.Option([], "--host", help="A name or address the router is reached by (repeatable)."),
    issue: str = typer.Option(
        "",
        "--issue",
        metavar="NAME",
        help="Issue host NAME its own certificate, signed by DIR's authority, in DIR/hosts/NAME/.",
    ),
    system: str = typer.Option(
        "",
        "--system",
        metavar="ENDPOINT",
        help="With --issue: also put the running --secure system's credentials entry (ENDPOINT's) in that folder.",
    ),
) -> None:
    """Make a certificate authority and the router's and clients' certificates for
    `launch --secure --tls DIR` (mutual TLS); the keys are readable by you only.  Another
    machine that joins copies ca.pem, client.pem and client.key and sets TURTLECTL_TLS; or,
    with --issue NAME, gets a folder of its own (its own certificate, which `launch --deny-host
    NAME` can shut out, and with --system the running system's credentials entry it logs in
    with, given again after each launch: every launch makes new logins): copy that folder to
    the host and set the variables printed.

    Example: turtlectl certs ~/.turtlectl/tls --issue robot7 --system tls/192.168.1.20:7447
    """
    from turtlectl.cli.system import certs as tls_certs
    from turtlectl.runtime.client import credentials

    if not issue:
        if system:
            raise BadInput("--system goes with --issue NAME (the host whose folder gets the entry)")
        written = tls_certs.make(folder, host)
        result("wrote " + ", ".join(str(p) for p in written))
        return
    where = folder / tls_certs.HOSTS / issue
    written = [] if (where / "client.pem").exists() and system else tls_certs.issue(folder, issue)
    if system:
        written.append(tls_certs.hand_credentials(folder, issue, credentials.entry_text(checks.endpoint(system))))
    lines = [f"wrote {', '.join(str(p) for p in written)}", f"on host {issue}: export TURTLECTL_TLS={where}"]
    if system:
        lines.append(f"on host {issue}: export TURTLECTL_CREDENTIALS={where / 'credentials.json'}")
    result("\n".join(lines))


def router(
    ctx: typer.Context,
    port: int = typer.Option(DEFAULT_PORT, "--port", min=1, max=65535, help="Port to listen on."),
    listen: str = typer.Option(
        "127.0.0.1", "--listen", help="Address to listen on, loopback as well (loopback alone by default)."
    ),
    insecure: bool = typer.Option(
        False, "--insecure", help="Listen beyond loopback without logins (anyone who reaches it can drive)."
    ),
) -> None:
    """Run a Zenoh router alone, for nodes started with `launch --connect` (as rmw_zenohd).

    Example: turtlectl router --port 7447
    """
    from turtlectl.cli.system.supervisor.router import run_router
    from turtlectl.runtime.session import listen_hosts

    if (ctx.obj or {}).get("connect") is not None:
        raise BadInput("router takes no --connect: it is the router the others connect to (see --port, --listen)")
    host = args.listen_address(listen)
    args.exposure(host, secure=False, insecure=insecure, can_secure=False)
    where = " and ".join(f"tcp/{h}:{port}" for h in listen_hosts(host))
    run_router(port, host, lambda: typer.echo(f"router listening on {where}; Ctrl-C stops it", err=False))


def run(
    node: str = typer.Argument(
        ..., metavar="NODE", help="A node of the launch file, or a node class: module:Class, ./file.py:Class."
    ),
    param: list[str] = typer.Option([], "--param", "-p", help="KEY=VALUE override (repeatable; a.b=1 for tables)."),
    file: Path | None = typer.Option(None, "--file", help="Launch file (default as for launch)."),
    arg: list[str] = typer.Option(
        [],
        "--arg",
        metavar="NAME=VALUE",
        help="A launch argument, NAME an [arg.NAME] of the launch file: --arg speed=2 (or speed:=2); one --arg each, repeatable.",
    ),
    name: str | None = typer.Option(
        None, "--name", help="A node class's name in the system (default: its class's, Patrol: patrol)."
    ),
    namespace: str = typer.Option(
        "",
        "--namespace",
        help="A node class's namespace: its keys are that turtle's (turtle2: turtle2/pose, turtle2/robot/status).",
    ),
    use_sim_time: bool = typer.Option(
        False,
        "--use-sim-time",
        help="Timers, timeouts and stamps on the simulator's clock (ROS's use_sim_time), e.g. beside launch --time-scale.",
    ),
    log_level: str = LogLevelOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Run one node in the foreground with the parameters the launch file gives it (and
    overrides), joining the system at --connect: for debugging, or on another machine.  A
    node class (module:Class, or ./file.py:Class from here) runs with its parameters' defaults
    and overrides, named after its class (Patrol: patrol) or --name, as `ros2 run` does; two
    nodes of one name both run (`turtlectl list` shows both), so give a second one its own.

    Example: turtlectl run navigator -p goal_timeout=60 --log-level DEBUG
    """
    import msgspec

    from turtlectl.cli.system.launchfile import NAME_RE, default_launch_file, load_launch
    from turtlectl.cli.system.overrides import class_plan, node_config
    from turtlectl.cli.system.supervisor.process import exec_node
    from turtlectl.runtime.config import NodeConfig
    from turtlectl.runtime.loader import is_file, is_target

    def on_sim_time(config: NodeConfig) -> NodeConfig:
        return msgspec.structs.replace(config, use_sim_time=True) if use_sim_time else config

    if not is_target(node) and is_file(node) and (node.endswith(".py") or Path(node).is_file()):
        raise BadInput(f"{node} names a file: add its node class, as {node}:ClassName")
    level = args.log_level(log_level)
    endpoint = checks.endpoint(connect)
    if name is not None and not NAME_RE.match(name):
        raise BadInput(f"--name {name!r}: use letters, digits, _ and - (like patrol2)")
    if is_target(node) and arg:
        raise BadInput(f"--arg gives a launch file's arguments; {node} is a node class (its parameters: -p KEY=VALUE)")
    if is_target(node):  # a node's name has no ':'
        plan, named = class_plan(node, param, Path.cwd(), name, namespace)
        typer.echo(f"running {node} as node {named} (turtlectl list shows it so; --name changes it)", err=True)
        exec_node(on_sim_time(node_config(plan, named, endpoint, None, domain, level)), plan.kinds[named])
    if name is not None or namespace:
        which = "--name renames" if name is not None else "--namespace places"
        raise BadInput(
            f"{which} a node class (module:Class, ./file.py:Class); {node} is named by its launch file "
            "(a namespaced node of it: turtle2/navigator)"
        )
    plan = load_launch(file or default_launch_file(), arg)
    exec_node(on_sim_time(node_config(plan, node, endpoint, param, domain, level)), plan.kinds[node])


def log_level_command(
    node: str = NodesArgument,
    level: str = typer.Argument(..., metavar="LEVEL", help="DEBUG, INFO, WARNING (or WARN) or ERROR, any case."),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Change a running node's log level at once (`launch --log-level` sets it for all at start);
    NODE may name several: a namespace or turtle (all its nodes), or a glob ('turtle2/*').

    Example: turtlectl log-level navigator DEBUG   or   turtlectl log-level 'turtle2/*' DEBUG
    """
    from turtlectl.cli.tools import introspect

    result(introspect.set_log_levels(connect, domain, node, level))


new_app = typer.Typer(help="Start something of your own (as `ros2 pkg create`).\n\nExample: turtlectl new node patrol")


@new_app.command("node")
def new_node(
    name: str = typer.Argument(..., metavar="NAME", help="The node's module name, snake_case (patrol, wall_follower)."),
    folder: Path = typer.Option(Path("."), "--dir", help="The project folder (default: here)."),
) -> None:
    """Write a node class to start from (NAME.py: its Params, Interface, a timer), its unit test
    (tests/test_NAME.py, with FakeNode) and a pytest.ini if there is none; print its launch-file
    entry.  Nothing is overwritten (exit 2).

    Example: turtlectl new node patrol
    """
    from turtlectl.cli.tools import scaffold

    files = scaffold.node_files(name, folder)
    for path, text in files.items():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    wrote = ", ".join(str(p) for p in files)
    result(
        f"wrote {wrote}\n\nadd to your launch.toml:\n\n{scaffold.launch_entry(name)}\n"
        f"then: turtlectl launch --check; turtlectl launch; pytest"
    )


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.add_typer(new_app, name="new")
    app.command(context_settings={"allow_extra_args": True})(launch)  # ROS's speed:=2 gets a hint
    app.command()(certs)
    app.command()(router)
    app.command()(run)
    app.command("log-level")(log_level_command)
