"""The options and arguments that several groups of commands share, and how a one-shot
command prints its result."""

from __future__ import annotations

import typer

from turtlectl.cli import args, lazy_module
from turtlectl.runtime.client import checks
from turtlectl.runtime.client.errors import BadInput
from turtlectl.runtime.client.sigint import ignore_sigint
from turtlectl.runtime.endpoint import CONNECT_ENV, DEFAULT_ENDPOINT, DOMAIN_ENV

format = lazy_module("turtlectl.cli.tools.format")  # msgspec and the message types load when a command prints one


def completer(kind: str):
    """A Typer ``autocompletion`` callback offering the running system's names of ``kind``
    (cli.tools.complete: topics, services, goal_services, nodes, turtles, parameters)."""

    def complete(ctx, incomplete):  # noqa: ANN001, ANN202 - Typer passes both by these names
        from turtlectl.cli.tools import complete as live

        return getattr(live, kind)(dict(ctx.params), incomplete)

    return complete


#: where the root's --connect (given before the command) is kept for the invocation
CONNECT_KEY = "turtlectl.connect"


def use_connect(ctx: typer.Context, param: typer.CallbackParam, connect: str) -> str:
    """``--connect`` after the command; when it is not given there, the one given before the
    command (``turtlectl --connect tcp/... list``), else TURTLECTL_CONNECT, else the default."""
    # by name: the enum is click's, which typer vendors (importing click itself costs --help ~15 ms)
    source = ctx.get_parameter_source(param.name or "connect")
    given_after = source is not None and source.name == "COMMANDLINE"
    return connect if given_after else ctx.meta.get(CONNECT_KEY, connect)


ConnectOption = typer.Option(
    DEFAULT_ENDPOINT,
    "--connect",
    envvar=CONNECT_ENV,
    callback=use_connect,
    help="Router endpoint of the system to talk to.",
)


#: where the domain chosen so far is kept for the invocation (the root's --domain, a node's ``lab1:``)
DOMAIN_KEY = "turtlectl.domain"


def use_domain(ctx: typer.Context, domain: str) -> str:
    """Check ``--domain``: the command's domain, which it hands to every session it opens; the
    same option before or after the command (``turtlectl --domain lab1 list`` = ``turtlectl list
    --domain lab1``): one not given after the command is the one before it (or a node's ``lab1:``)."""
    args.domain(domain)
    if not domain:
        domain = ctx.meta.get(DOMAIN_KEY, "")
    ctx.meta[DOMAIN_KEY] = domain
    return domain


DomainOption = typer.Option(
    "",
    "--domain",
    envvar=DOMAIN_ENV,
    callback=use_domain,
    help="Keys of the system live under this prefix (two systems never mix); before or after the command.",
)


JsonOption = typer.Option(False, "--json", help="One JSON object.")


def use_turtle(text: str) -> str:
    """``--turtle`` checked: a turtle's name (its nodes' namespace), or "" for turtle1."""
    return checks.turtle_name(text)


TurtleOption = typer.Option(
    "",
    "--turtle",
    callback=use_turtle,
    autocompletion=completer("turtles"),
    metavar="NAME",
    help="The turtle to act on (its nodes' namespace: turtle2 reaches turtle2/navigate_to, turtle2/robot/status); default turtle1.",
)


ExitOnLossOption = typer.Option(
    False,
    "--exit-on-loss",
    help="Exit with code 3 when the router is lost, instead of saying so and waiting for it to come back.",
)


LogLevelOption = typer.Option(
    "INFO", "--log-level", help="Least severe log line the nodes write: DEBUG, INFO, WARNING or ERROR (any case)."
)


def result(text: str) -> None:
    """Print a one-shot command's result: from now on a Ctrl-C changes nothing (no 130, no
    traceback from Zenoh's threads while the process ends)."""
    ignore_sigint()
    typer.echo(text)


def _in_domain(ctx: typer.Context, text: str, in_domain: str) -> None:
    """A node written with its domain (``lab1:navigator``, as `list` shows a node of domain lab1
    to a client without --domain) makes that the domain of this command."""
    if in_domain:
        chosen = ctx.meta.get(DOMAIN_KEY, "")
        if chosen and chosen != in_domain:
            raise BadInput(f"node {text!r} is in domain {in_domain!r}, not in --domain {chosen!r}")
        ctx.meta[DOMAIN_KEY] = in_domain


def use_node(ctx: typer.Context, text: str | None) -> str | None:
    """NODE checked; ``lab1:navigator`` makes lab1 the domain of this command."""
    if text is None:
        return None
    in_domain, name = args.node_name(text)
    _in_domain(ctx, text, in_domain)
    return name


def use_nodes(ctx: typer.Context, text: str | None) -> str | None:
    """NODE as a selector (a name, namespace, turtle or glob: cli.selection), checked."""
    if text is None:
        return None
    in_domain, selector = args.node_selector(text)
    _in_domain(ctx, text, in_domain)
    return selector


NodeArgument = typer.Argument(
    ...,
    metavar="NODE",
    callback=use_node,
    autocompletion=completer("nodes"),
    help="A node's name, as `turtlectl list` shows it (turtle2/navigator: in namespace turtle2; lab1:sim: in domain lab1).",
)

NodesArgument = typer.Argument(
    ...,
    metavar="NODE",
    callback=use_nodes,
    autocompletion=completer("nodes"),
    help="A node's name as `turtlectl list` shows it, a namespace or turtle (all its nodes: turtle2), "
    "or a glob ('turtle2/*', '*/navigator').",
)
