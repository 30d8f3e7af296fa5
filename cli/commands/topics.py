"""turtlectl's Topics commands: echo, hz, pub, and topic info.

Sessions and rates (cli.tools.topics, cli.tools.rates) are imported inside each command."""

from __future__ import annotations

import sys
from typing import Any

import typer

from turtlectl.cli import args
from turtlectl.cli.commands.options import (
    ConnectOption,
    DomainOption,
    ExitOnLossOption,
    JsonOption,
    TurtleOption,
    completer,
    format,
    result,
)
from turtlectl.runtime.client.errors import Interrupted, Unreachable


def echo(
    topic: str = typer.Argument(
        ..., metavar="TOPIC", autocompletion=completer("topics"), help="Key expression, e.g. robot/status or turtle1/*."
    ),
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
    exit_on_loss: bool = ExitOnLossOption,
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Print the messages published on TOPIC, decoded whatever their type (with --turtle turtle2,
    TOPIC as turtle2's nodes write it: robot/status is turtle2/robot/status).

    Keeps printing across a publisher's restart; runs until Ctrl-C (exit code 0), --count or
    --timeout.  When nothing arrives for 3 s (from the start, or after messages flowed) it says
    why on stderr, once per silence.  A lost router is said on stderr and waited for (one
    line when it is back); --exit-on-loss exits with code 3 instead.  With a wildcard each
    message names its key.  Example: turtlectl echo robot/status --field battery
    """
    from turtlectl.cli.tools import topics
    from turtlectl.messages.keys import resolve
    from turtlectl.runtime.client.session import turtle_namespace_at

    args.one_format(json, csv)
    limit = args.echo_limit(once, count)
    topic = resolve(topic, turtle_namespace_at(connect, turtle, domain))
    wildcard = "*" in topic
    fields = list(dict.fromkeys(field))  # each once, in the order typed
    skipped: dict[str, int] = {}
    try:
        _echo(
            topics.stream(connect, domain, topic, limit, timeout, exit_on_loss),
            skipped,
            fields,
            json,
            csv,
            full,
            wildcard,
        )
    except KeyboardInterrupt:
        pass
    except BrokenPipeError:  # `| head`: the reader has what it wanted
        sys.stderr.close()
        return
    finally:  # the undecodable payloads, counted: said however echo ends (a --timeout included)
        for key, count in skipped.items():
            if count > 1:
                typer.echo(f"skipped {count} messages on {key} in all", err=True)


def _echo(
    stream: Any,
    skipped: dict[str, int],
    fields: list[str],
    json: bool,
    csv: bool,
    full: bool,
    wildcard: bool,
) -> None:
    """Print each message of ``stream`` as echo's options say (``skipped``: undecodable ones, by key)."""
    from turtlectl.cli.tools import topics

    header = False
    for item in stream:
        if isinstance(item, topics.Notice):  # a silence and why, a type described two ways
            typer.echo(item.text, err=True)
            continue
        if item.message is None and item.generic is None:  # not decodable at all: named once per key, counted
            skipped[item.key] = skipped.get(item.key, 0) + 1
            if skipped[item.key] == 1:
                typer.echo(f"skipped a message on {item.key}: {item.problem} (more are counted)", err=True)
            continue
        msg = item.message if item.message is not None else format.Undescribed(item.generic, item.unknown)
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


def hz(
    names: list[str] = typer.Argument(
        ..., metavar="TOPIC...", autocompletion=completer("topics"), help="One or more key expressions."
    ),
    window: int = typer.Option(100, "--window", min=2, help="At most N messages (of the last 5 s) per statistic."),
    duration: float | None = typer.Option(None, "--duration", min=0.5, help="Stop after S seconds."),
    json: bool = typer.Option(False, "--json", help="JSON lines."),
    exit_on_loss: bool = ExitOnLossOption,
    turtle: str = TurtleOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Rate of each TOPIC from arrival times (with jitter), and the publisher's own rate from
    stamps (with --turtle turtle2, each TOPIC as turtle2's nodes write it).

    Each second, a line for each TOPIC that had messages since the last one, over the messages
    of the last 5 s; a topic silent for 3 s (from the start, or after it stopped) is reported with
    the reason, once per silence.  A lost router is said on stderr and waited for (one line when
    it is back; --exit-on-loss exits with code 3 instead).  Runs until Ctrl-C (exit code 0) or
    --duration.  Example: turtlectl hz robot/status obstacles --duration 10
    """
    from turtlectl.cli.tools import topics
    from turtlectl.cli.tools.rates import rate_line
    from turtlectl.messages.keys import resolve
    from turtlectl.runtime.client.session import turtle_namespace_at

    printed = False
    namespace = turtle_namespace_at(connect, turtle, domain)
    names = [resolve(name, namespace) for name in names]
    try:
        for stats in topics.measure_rates(connect, domain, names, window, duration, exit_on_loss):
            if isinstance(stats, topics.Notice):  # a silence and why, the router lost or back
                typer.echo(stats.text, err=True)
                continue
            printed = printed or bool(stats)
            for st in stats:
                typer.echo(format.json_value(st) if json else rate_line(st))
    except KeyboardInterrupt:
        pass
    if duration is not None and not printed:
        raise Unreachable(f"no messages on {', '.join(names)} within {duration:g} s")


def pub(
    topic: str = typer.Argument(..., metavar="TOPIC", autocompletion=completer("topics"), help="Key to publish on."),
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
    from turtlectl.cli.tools import build, topics
    from turtlectl.messages.codec import type_name as full_name
    from turtlectl.runtime.client import session as client

    key = client.check_key(topic, publish=True)
    type_name = topics.learn_type(
        connect, domain, client.base_key(key, domain), type_name
    )  # yours: from the nodes using it
    msg = build.topic_message(client.base_key(key, domain), message, type_name)
    count = args.publish_count(once, rate, times)
    try:
        sent = topics.publish(connect, domain, topic, msg, rate if rate is not None else 10.0, count)
    except KeyboardInterrupt:
        if count is not None:
            raise Interrupted("interrupted before every message was sent") from None
        return
    typer.echo(f"published {sent} {full_name(type(msg))} on {key}", err=True)


topic_app = typer.Typer(
    help="One topic in detail (as `ros2 topic info`); echo, hz and pub are commands of their own.\n\n"
    "Example: turtlectl topic info turtle1/pose -v"
)


@topic_app.command("info")
def topic_info(
    key: str = typer.Argument(
        ..., metavar="KEY", autocompletion=completer("topics"), help="A topic's key, e.g. turtle1/pose."
    ),
    verbose: bool = typer.Option(False, "-v", "--verbose", help="Also measure its rate over a second."),
    json: bool = JsonOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """A topic's type, and its publishers and subscribers with their nodes (pid, host); with
    -v, its rate measured over one second.

    Example: turtlectl topic info turtle1/pose -v
    """
    from turtlectl.cli.tools import introspect

    report = introspect.topic_report(connect, domain, key, verbose)
    result(format.json_value(report) if json else introspect.topic_text(report))


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.command()(echo)
    app.command()(hz)
    app.command()(pub)
    app.add_typer(topic_app, name="topic")
