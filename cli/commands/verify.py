"""The ``verify`` command: a specification file checked against a running system, or one it
launches (thin over cli.verify)."""

from __future__ import annotations

from pathlib import Path

import typer

from turtlectl.cli.commands.options import ConnectOption, DomainOption, JsonOption, result
from turtlectl.runtime.client.errors import BadInput, ExitCode


def verify(
    spec: Path = typer.Argument(..., metavar="SPEC", help="A specification file (TOML): docs/capstone.toml is one."),
    launch: Path | None = typer.Option(
        None, "--launch", help="Start this launch file on a free port for the check, and stop it after."
    ),
    launch_file: Path | None = typer.Option(
        None,
        "--launch-file",
        metavar="FILE",
        help="The launch file the running system was started from: the parameters criterion compares with it.",
    ),
    short: float | None = typer.Option(
        None,
        "--short",
        metavar="SECONDS",
        min=1.0,
        help="Run each long criterion (no_errors) for at most SECONDS, not its full time; the table says so.",
    ),
    time_scale: float | None = typer.Option(
        None,
        "--time-scale",
        metavar="F",
        min=0.1,
        max=20.0,
        help="With --launch: run it F times as fast (launch --time-scale) and measure in its simulated time.",
    ),
    use_sim_time: bool = typer.Option(
        False,
        "--use-sim-time",
        help="Measure in the simulated time of the system's clock (without it: when its clock runs at another factor than 1).",
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
    Long criteria run their full time unless --short says otherwise; --time-scale 5 runs them
    in simulated time, five times as fast.  The parameters criterion compares each node's
    parameters with the launch file (--launch, or --launch-file for a system already running).

    Example: turtlectl verify docs/capstone.toml --launch launch.toml --time-scale 5
    """
    from turtlectl.cli.system.launched import LaunchedSystem
    from turtlectl.cli.system.launchfile import LaunchPlan
    from turtlectl.cli.verify import checks, report
    from turtlectl.cli.verify.parameters import launch_file_plan
    from turtlectl.cli.verify.report import Verdict
    from turtlectl.cli.verify.spec import Parameters, load_spec
    from turtlectl.cli.verify.timebase import system_time
    from turtlectl.runtime.client.api import Client

    loaded = load_spec(spec)

    def progress(what: str) -> None:
        typer.echo(f"measuring: {what}", err=True)

    if time_scale is not None and launch is None:
        raise BadInput("--time-scale starts the system it checks faster: give --launch FILE (or --use-sim-time)")
    if launch is not None and launch_file is not None:
        raise BadInput("--launch-file names a running system's launch file: with --launch, that file is compared")
    compares = any(isinstance(c, Parameters) for c in loaded.criterion)

    def measured(client: Client, plan: LaunchPlan | None) -> list[Verdict]:
        clock = system_time(client, use_sim_time or time_scale is not None, progress)
        try:
            return checks.verify(client, loaded, progress, short, clock, plan)
        finally:
            clock.close()

    if launch is not None:
        scale = ("--time-scale", f"{time_scale:g}") if time_scale is not None else ()
        with LaunchedSystem(launch, scale) as system, system.client() as client:
            verdicts = measured(client, launch_file_plan(launch, time_scale) if compares else None)
    else:
        plan = launch_file_plan(launch_file) if compares and launch_file is not None else None
        with Client(connect, domain) as client:
            verdicts = measured(client, plan)
    if junit is not None:
        report.write_junit(junit, str(spec), verdicts)
    result(report.as_json(verdicts) if json else report.table(verdicts))
    raise typer.Exit(ExitCode.OK if all(v.ok for v in verdicts) else ExitCode.FAILED)


def register(app: typer.Typer) -> None:
    app.command()(verify)
