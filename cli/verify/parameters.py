"""The ``parameters`` criterion of a specification: each node runs with the parameters it was
meant to, measured through a ``turtlectl.Client`` (the query ``turtlectl param dump`` makes)
against a launch file, read by the code ``turtlectl launch`` reads it with, and against the
values the specification gives.  ``differences`` and ``expected_nodes`` are pure."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from turtlectl.cli.system.launchfile import LaunchPlan
from turtlectl.cli.tools.params import toml_value
from turtlectl.cli.verify.report import Verdict
from turtlectl.cli.verify.spec import Parameters, label
from turtlectl.runtime.client.api import Client
from turtlectl.runtime.client.errors import BadInput, TurtlectlError
from turtlectl.runtime.loader import suggestion

#: what the table says when neither a launch file nor values are given to compare with
NOTHING_TO_COMPARE = (
    "no launch file to compare with: verify --launch FILE starts one, --launch-file FILE names the one "
    "a running system was started from (or give the values in the criterion's params)"
)


def launch_file_plan(path: Path, time_scale: float | None = None) -> LaunchPlan:
    """The launch file at ``path`` as ``turtlectl launch`` runs it (with ``--time-scale``, its
    simulator's factor and every node's use_sim_time as launch sets them); LaunchFileError
    (exit 2) naming the key when it cannot be used."""
    from turtlectl.cli.system.overrides import launch_plan

    return launch_plan(path, [], [], [], time_scale)


def expected_nodes(plan: LaunchPlan) -> dict[str, tuple[str, dict[str, Any]]]:
    """Each turtlectl node of ``plan`` by its full name: its kind (the launch file's ``run``) and
    its parameters, defaults filled in (a ``cmd`` program is no turtlectl node: left out)."""
    return {e.name: (e.run, plan.params[e.name]) for e in plan.launch.node if e.name not in plan.commands}


def _shown(value: Any) -> str:
    """A parameter's value as a launch file writes it (a value TOML has no form for: as JSON)."""
    try:
        return toml_value(value)
    except BadInput:
        return json.dumps(value, default=str)


def _same(expected: Any, actual: Any) -> bool:
    """Equal as values (30 and 30.0 are; true and 1 are not)."""
    if isinstance(expected, bool) or isinstance(actual, bool):
        return isinstance(expected, bool) and isinstance(actual, bool) and expected == actual
    if isinstance(expected, dict) and isinstance(actual, dict):
        return expected.keys() == actual.keys() and all(_same(v, actual[k]) for k, v in expected.items())
    if isinstance(expected, list | tuple) and isinstance(actual, list | tuple):
        return len(expected) == len(actual) and all(_same(a, b) for a, b in zip(expected, actual, strict=True))
    return bool(expected == actual)


def differences(node: str, expected: dict[str, Any], actual: dict[str, Any], source: str, whole: bool) -> list[str]:
    """Each parameter of ``node`` whose running value (``actual``) is not ``expected``'s, one
    line each naming node, parameter, expected and actual (``source``: where the expected value
    is written).  ``whole``: every parameter must match both ways (a launch file's, defaults
    filled in); else only those ``expected`` names (a table's given keys too)."""
    out: list[str] = []

    def walk(want: dict[str, Any], got: dict[str, Any], prefix: str) -> None:
        for name, value in want.items():
            path = f"{prefix}{name}"
            if name not in got:
                hint = suggestion(name, list(got))
                out.append(f"{node}.{path}: {source} {_shown(value)}, the node has no such parameter{hint}")
            elif isinstance(value, dict) and isinstance(got[name], dict) and not whole:
                walk(value, got[name], f"{path}.")
            elif not _same(value, got[name]):
                out.append(f"{node}.{path}: {source} {_shown(value)}, running {_shown(got[name])}")
        if whole:
            for name in got.keys() - want.keys():
                out.append(f"{node}.{prefix}{name}: running {_shown(got[name])}, {source} has no such parameter")

    walk(expected, actual, "")
    return out


def parameters(client: Client, c: Parameters, plan: LaunchPlan | None) -> Verdict:
    """Every node of ``plan`` (None: no launch file given) runs with its kind and the launch
    file's parameters, and every node of ``c.params`` with those values."""
    declared = expected_nodes(plan) if plan is not None else {}
    sources = ([plan.source] if plan is not None else []) + (["the spec's params"] if c.params else [])
    required = f"{len(declared) or len(c.params)} nodes with the parameters of {' and '.join(sources) or 'nothing'}"
    if plan is None and not c.params:
        return Verdict(label(c), required, "nothing compared", False, NOTHING_TO_COMPARE)
    alive = {n.name for n in client.nodes()}
    problems: list[str] = []
    differ: list[str] = []
    compared: set[str] = set()
    running: dict[str, dict[str, Any] | None] = {}

    def params_of(name: str) -> dict[str, Any] | None:
        if name not in running:
            try:
                running[name] = client.params(name)
            except TurtlectlError as exc:
                problems.append(f"{name}: its parameters could not be read ({exc.message})")
                running[name] = None
        return running[name]

    for name, (kind, expected) in declared.items():
        if name not in alive:
            problems.append(f"{name} does not run (the launch file starts it: {kind})")
            continue
        try:
            told = client.node_info(name).kind
        except TurtlectlError as exc:
            problems.append(f"{name}: it did not say what it is ({exc.message})")
            told = kind
        if told != kind:
            problems.append(f"{name} runs {told or 'an unnamed kind'}, the launch file says run = {kind!r}")
        got = params_of(name)
        if got is not None:
            compared.add(name)
            differ += differences(name, expected, got, "the launch file", whole=True)
    for name, values in c.params.items():
        if name not in alive:
            problems.append(f"{name} does not run (the spec gives its parameters)")
            continue
        got = params_of(name)
        if got is not None:
            compared.add(name)
            differ += differences(name, values, got, "the spec", whole=False)
    problems += differ
    measured = f"{len(compared)} nodes' parameters read, {len(differ)} differ"
    return Verdict(label(c), required, measured, not problems, "; ".join(problems))
