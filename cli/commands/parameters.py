"""turtlectl's Parameters commands: param list, get, set, describe, dump.

The logic (cli.tools.params) is imported inside each command."""

from __future__ import annotations

import typer

from turtlectl.cli.commands.options import (
    ConnectOption,
    DomainOption,
    JsonOption,
    NodeArgument,
    NodesArgument,
    TurtleOption,
    completer,
    format,
    result,
    use_node,
)

param_app = typer.Typer(
    help="A running node's parameters: list, get, set, describe, dump (as `ros2 param`).\n\n"
    "Example: turtlectl param set navigator goal_timeout 60"
)


ParamArgument = typer.Argument(
    ...,
    metavar="NAME",
    autocompletion=completer("parameters"),
    help="A parameter, e.g. goal_timeout or gains.lookahead.",
)


@param_app.command("list")
def param_list(
    node: str | None = typer.Argument(
        None,
        metavar="[NODE]",
        callback=use_node,
        autocompletion=completer("nodes"),
        help="A node's name (default: every running node).",
    ),
    json: bool = typer.Option(False, "--json", help="One JSON array of names (by node without NODE)."),
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """The names of a running node's parameters (a table's entries dotted: gains.lookahead),
    or of every node's.

    Example: turtlectl param list navigator
    """
    from turtlectl.cli.tools import params
    from turtlectl.runtime.client.session import node_of_turtle

    if node is None:
        by_node = params.listing_all(connect, domain)  # every node's: --turtle names none
        result(format.json_value(by_node) if json else params.listing_text(by_node))
        return
    node = node_of_turtle(connect, node, turtle, domain)
    names = params.names(params.fetch(connect, domain, node))
    result(format.json_value(names) if json else "\n".join(names))


@param_app.command("set", context_settings={"ignore_unknown_options": True})  # negative VALUEs
def param_set(
    node: str = NodesArgument,
    name: str = ParamArgument,
    value: str = typer.Argument(
        ..., metavar="VALUE", help='A TOML value as in a launch file: 60, 0.5, true, [1, 2], "text".'
    ),
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Change a parameter of a running node at once, validated as the launch file is (same
    errors, exit 2; a node of your own kind: as it describes its parameters, and by the node);
    parameters that cannot change at run time are refused with the reason.
    The node publishes a ParameterEvent (`turtlectl echo turtlectl/parameter_events`).  A node
    that is started again (respawn) runs with the launch file's value unless the system was
    launched with --persist.  NODE may name several (a namespace, a turtle, a glob:
    '*/navigator'): each is set, its answer on a line of its own.

    Example: turtlectl param set navigator goal_timeout 60 --turtle turtle2
    """
    from turtlectl.cli.tools import params
    from turtlectl.cli.tools.introspect import nodes_named
    from turtlectl.runtime.client.session import node_of_turtle

    node = node_of_turtle(connect, node, turtle, domain)
    chosen = nodes_named(connect, domain, node)
    if chosen is None:
        result(params.set_value(connect, domain, node, name, value))
        return
    result("\n".join(f"{n}: {params.set_value(connect, domain, n, name, value)}" for n in chosen))


@param_app.command("describe")
def param_describe(
    node: str = NodeArgument,
    name: str = ParamArgument,
    json: bool = JsonOption,
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """A parameter's type, unit, range, default, meaning, value now, and whether it can change
    at run time.

    Example: turtlectl param describe navigator goal_timeout
    """
    from turtlectl.cli.tools import params
    from turtlectl.runtime.client.session import node_of_turtle

    node = node_of_turtle(connect, node, turtle, domain)
    info, now = params.describe(connect, domain, node, name)
    if json:
        result(format.json_value({**params.plain(info), "value": now}))
    else:
        result(params.describe_text(node, info, now))


@param_app.command("get")
def param_get(
    node: str = NodesArgument,
    name: str = ParamArgument,
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """One parameter's value as the node runs with it, in JSON; NODE may name several (a
    namespace, a turtle, a glob: '*/navigator'), each then on a line of its own, "NODE: VALUE".

    Example: turtlectl param get navigator goal_timeout --turtle turtle2
    """
    from turtlectl.cli.tools import params
    from turtlectl.cli.tools.introspect import nodes_named
    from turtlectl.runtime.client import answers
    from turtlectl.runtime.client.session import node_of_turtle

    node = node_of_turtle(connect, node, turtle, domain)
    chosen = nodes_named(connect, domain, node)
    if chosen is None:
        result(format.json_value(answers.value(params.fetch(connect, domain, node), node, name)))
        return
    values = {n: format.json_value(answers.value(params.fetch(connect, domain, n), n, name)) for n in chosen}
    result("\n".join(f"{n}: {v}" for n, v in values.items()))


@param_app.command("dump")
def param_dump(
    node: str = NodeArgument,
    json: bool = typer.Option(False, "--json", help="One JSON object instead of TOML."),
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Every parameter of a running node, as TOML for its [node.params] table in a launch file.

    Example: turtlectl param dump navigator > navigator.toml
    """
    from turtlectl.cli.tools import params
    from turtlectl.runtime.client.session import node_of_turtle

    node = node_of_turtle(connect, node, turtle, domain)
    values = params.fetch(connect, domain, node)
    result(format.json_value(values) if json else params.dump(node, values))


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.add_typer(param_app, name="param")
