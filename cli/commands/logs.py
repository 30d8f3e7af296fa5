"""turtlectl's ``log`` command: every node's log in one place (registered with the
Introspection group; the logic is cli.tools.log, imported inside the command)."""

from __future__ import annotations

import sys
import time

import typer

from turtlectl.cli.commands.options import ConnectOption, DomainOption, ExitOnLossOption, completer
from turtlectl.runtime.client.errors import Interrupted


def log(
    level: str | None = typer.Option(
        None,
        "--level",
        "-l",
        metavar="LEVEL",
        help="Only records at LEVEL or above: DEBUG, INFO, WARNING (WARN), ERROR or CRITICAL (FATAL), any case.",
    ),
    node: list[str] = typer.Option(
        [],
        "--node",
        "-n",
        metavar="NAME",
        autocompletion=completer("nodes"),
        help="Only this node's records; a glob matches several (turtle2/*); repeatable.",
    ),
    follow: bool = typer.Option(
        False, "--follow", "-f", help="After the recent records, print each new one as it comes, until Ctrl-C."
    ),
    since: str | None = typer.Option(
        None,
        "--since",
        metavar="DURATION",
        help="Only records of the last DURATION: 30s, 5m, 1h30m, 250ms (a bare number is seconds).",
    ),
    json: bool = typer.Option(False, "--json", help="One JSON object per line (a Log message, as echo --json)."),
    exit_on_loss: bool = ExitOnLossOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Every running node's log in one place (as rqt_console and ROS's /rosout), merged by
    time: the records each node still holds (its last 200), then with --follow each new one.

    Nodes publish every record at their log level (`turtlectl log-level NODE DEBUG` for
    more), hand-run nodes (`turtlectl run`) included, on turtlectl/log/<node>.  Colours by
    level on a terminal (none when piped, or with NO_COLOR set).  No running node (or none
    matching --node) is exit code 3 without --follow; with it, it waits for them.  Ctrl-C
    ends --follow with exit code 0 (130 before a read without it is done).  With --follow, a
    lost router is said on stderr and waited for (one line when it is back); --exit-on-loss
    exits with code 3 instead.

    Example: turtlectl log --level WARNING --since 5m
    """
    from turtlectl.cli.tools import log as logs

    wanted = logs.LogFilter(
        level=logs.level_number(level) if level is not None else 0,
        nodes=tuple(dict.fromkeys(node)),
        since_ns=time.time_ns() - int(logs.since_seconds(since) * 1e9) if since is not None else 0,
    )
    colour = not json and logs.use_colour(sys.stdout.isatty())
    try:
        for item in logs.read(connect, domain, wanted, follow, exit_on_loss):
            if isinstance(item, logs.Notice):
                typer.echo(item.text, err=True)
            else:
                typer.echo(logs.json_of(item) if json else logs.text_of(item, colour))
    except KeyboardInterrupt:
        if not follow:  # a one-shot read stopped before its end
            raise Interrupted("interrupted before every record was read") from None
    except BrokenPipeError:  # `| head`: the reader has what it wanted
        sys.stderr.close()


def register(app: typer.Typer) -> None:
    """Add this command to ``app``."""
    app.command()(log)
