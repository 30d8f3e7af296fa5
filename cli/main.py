"""``turtlectl``: the command-line interface (Typer): the app, its root options, the groups
of commands, and the one place where errors become exit codes.

Each group of commands is a module of cli.commands (system, driving, topics, services,
parameters, introspection, recording), a thin layer of Typer commands: they parse options,
call logic that never prints (client tools in cli.tools, the launch side in cli.system,
recordings in cli.recording, the Foxglove bridge in cli.foxglove; argument checks in
cli.args), and print what it returns.  Logic raises errors by meaning (runtime.client.errors); ``main``
is the one place that prints them on stderr and exits with their exit code.

``turtlectl --help`` must stay quick: modules that cost time to import (sessions, launch
files and node parameters, the supervisor, the curses view, the version metadata) are
imported inside the commands that use them, not in the group modules nor here.
"""

from __future__ import annotations

import signal
import sys
from typing import Any

import typer
import typer.core

from turtlectl.cli import STOPPED_BY_CTRL_C
from turtlectl.cli.commands import (
    actions,
    driving,
    introspection,
    parameters,
    plotting,
    recording,
    ros2,
    services,
    specification,
    system,
    topics,
    turtles,
    verify,
    web,
)
from turtlectl.cli.commands.options import CONNECT_KEY, DomainOption
from turtlectl.runtime.client import presence
from turtlectl.runtime.client.errors import BadInput, ExitCode, Interrupted, TurtlectlError, exit_code
from turtlectl.runtime.client.sigint import ignore_sigint, quiet_unraisable
from turtlectl.runtime.endpoint import CONNECT_ENV, DEFAULT_ENDPOINT, peer_timeout

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
    "System": ("launch", "router", "run", "new", "verify", "spec", "log-level", "certs"),
    "Goals and driving": ("goto", "cancel", "teleport", "reset", "teleop", "spawn", "kill"),
    "Topics": ("echo", "hz", "pub", "topic", "plot"),
    "Services": ("call", "action"),
    "Parameters": ("param",),
    "Introspection": ("list", "node", "log", "interface", "view", "web"),
    "Recording and Foxglove": ("record", "info", "play", "recover", "foxglove"),
    "ROS 2": ("ros2",),
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


def _print_version(value: bool) -> None:
    if value:
        from turtlectl.cli.version import version

        typer.echo(f"turtlectl {version()}")
        raise typer.Exit(0)


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
    presence.set_tool(ctx.invoked_subcommand or "turtlectl")  # its client sessions are listed as this tool
    try:
        peer_timeout()  # every session this process and its nodes open reads it: wrong, nothing starts
    except ValueError as exc:
        raise BadInput(str(exc)) from None
    if ctx.invoked_subcommand not in STOPPED_BY_CTRL_C:
        # client commands handle Ctrl-C as KeyboardInterrupt (goto cancels, echo stops);
        # launch and router keep cli.entry's quiet handler until they install their own
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if connect is not None:  # the commands' --connect when they are given none of their own (options.use_connect)
        ctx.meta[CONNECT_KEY] = connect
        ctx.obj = {"connect": connect}  # launch joins it, as with its own --connect; router refuses it


#: the modules of the groups of commands, in COMMAND_GROUPS' order
GROUPS = (
    system,
    driving,
    turtles,
    topics,
    plotting,
    services,
    actions,
    parameters,
    introspection,
    recording,
    verify,
    specification,
    ros2,
    web,
)
for group in GROUPS:
    group.register(app)


def error_line(error: TurtlectlError) -> str:
    """What the user reads on stderr for ``error`` (a Ctrl-C is no error: its message says what happened)."""
    return f"turtlectl: {error.message}" if isinstance(error, Interrupted) else f"turtlectl: error: {error.message}"


def main() -> None:
    """Console entry point: run the app; the one place where an error becomes its message on
    stderr and its exit code (runtime.client.errors.exit_code)."""
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
