"""The ``spec`` commands: a specification file shown as the capstone's Markdown template, and
a specification's skeleton written from a running system (thin over cli.verify)."""

from __future__ import annotations

from pathlib import Path

import typer

from turtlectl.cli.commands.options import ConnectOption, DomainOption, result

spec_app = typer.Typer(
    help="Specification files (TOML, as `turtlectl verify` checks them): show one as the capstone's "
    "Markdown template, or start one from a running system.\n\n"
    "Example: turtlectl spec show docs/capstone.toml"
)


@spec_app.command("show")
def show(
    spec: Path = typer.Argument(..., metavar="SPEC", help="A specification file (TOML): docs/capstone.toml is one."),
) -> None:
    """Print a specification as the capstone's Markdown template: Intent, System Architecture
    (each node's input, output and purpose), Interfaces (each service and topic with its types,
    frequency, publishers and subscribers), Success Criteria (each an unchecked box, with its
    numbers: `verify` gives the verdicts) and Non-Goals.  A bad file is exit code 2, naming the key.

    Example: turtlectl spec show docs/capstone.toml > SPEC.md
    """
    from turtlectl.cli.verify.document import markdown
    from turtlectl.cli.verify.spec import load_spec

    result(markdown(load_spec(spec)).rstrip("\n"))


@spec_app.command("from-system")
def from_system(
    output: Path | None = typer.Option(
        None, "-o", "--output", help="The specification file to write (replaced if it exists).  [default: stdout]"
    ),
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Write a specification's skeleton from a running system: a placeholder intent; each node
    with the keys it subscribes to or serves (inputs) and publishes (outputs); each published
    topic with its type, its publisher and its period measured over 2 s (from the messages'
    stamps) with a 10 % tolerance (at least 5 ms); each service with its request type and
    server; a period criterion for each measured topic; a parameters criterion with each
    node's parameters as it runs with them; no non-goals.  Edit it into a real specification;
    as written, `turtlectl verify` passes it on the same system.

    Example: turtlectl spec from-system -o my_spec.toml && turtlectl verify my_spec.toml
    """
    from turtlectl.cli.verify import document, report, skeleton
    from turtlectl.runtime.client.api import Client

    with Client(connect, domain) as client:
        text = document.to_toml(skeleton.from_system(client))
    if output is None:
        result(text.rstrip("\n"))
    else:
        report.write(output, text, f"cannot write {output}")
        result(f"wrote {output}")


def register(app: typer.Typer) -> None:
    """Add this group's commands to ``app``."""
    app.add_typer(spec_app, name="spec")
