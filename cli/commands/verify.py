"""The ``verify`` command: a specification file checked against a running system, or one it
launches (thin over cli.verify)."""

from __future__ import annotations

from pathlib import Path

import typer

from turtlectl.cli.commands.options import ConnectOption, DomainOption, JsonOption, result
from turtlectl.cli.errors import ExitCode


def verify(
    spec: Path = typer.Argument(..., metavar="SPEC", help="A specification file (TOML): docs/capstone.toml is one."),
    launch: Path | None = typer.Option(
        None, "--launch", help="Start this launch file on a free port for the check, and stop it after."
    ),
    short: float | None = typer.Option(
        None,
        "--short",
        metavar="SECONDS",
        min=1.0,
        help="Run each long criterion (no_errors) for at most SECONDS, not its full time; the table says so.",
    ),
    junit: Path | None = typer.Option(
        None, "--junit", metavar="FILE", help="Also write the verdicts as a JUnit XML report to FILE (for CI)."
    ),
    json: bool = JsonOption,
    connect: str = ConnectOption,
    domain: str = DomainOption,
) -> None:
    """Check a running system against a specification: each topic and service it declares
    (present, its type, its publisher, its period) and each success criterion, measured; one
    table of what was required, what was measured and the verdict, the reason beside each
    failure.  Exit code 0 when all hold, 1 when one does not, 2 for a bad spec, 3 for no system.
    Long criteria run their full time unless --short says otherwise.

    Example: turtlectl verify docs/capstone.toml --launch launch.toml
    """
    from turtlectl.cli.system.launched import LaunchedSystem
    from turtlectl.cli.tools.api import Client
    from turtlectl.cli.verify import checks, report
    from turtlectl.cli.verify.spec import load_spec

    loaded = load_spec(spec)

    def progress(what: str) -> None:
        typer.echo(f"measuring: {what}", err=True)

    if launch is not None:
        with LaunchedSystem(launch) as system, system.client() as client:
            verdicts = checks.verify(client, loaded, progress, short)
    else:
        with Client(connect) as client:
            verdicts = checks.verify(client, loaded, progress, short)
    if junit is not None:
        report.write_junit(junit, str(spec), verdicts)
    result(report.as_json(verdicts) if json else report.table(verdicts))
    raise typer.Exit(ExitCode.OK if all(v.ok for v in verdicts) else ExitCode.FAILED)


def register(app: typer.Typer) -> None:
    app.command()(verify)
