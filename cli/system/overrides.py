"""Overrides of a launch plan (pure: no zenoh): ``launch --set NODE.PARAM=VALUE`` or ``--set
world.size=20``, ``run NODE -p PARAM=VALUE``, and ``param set`` against what runs now, each
applied to the plan's data and validated again as a launch file is (cli.system.launchfile);
what ``launch`` runs (``launch_plan``: the file, its ``--only``/``--exclude`` selection,
``select_nodes``, then its ``--set``) and what a node is started with (``node_config``).
"""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import msgspec

from turtlectl.cli.selection import selected, unmatched
from turtlectl.cli.system.launchfile import (
    TABLES,
    LaunchFileError,
    LaunchPlan,
    Report,
    load_launch,
    suggestion,
    validate,
)
from turtlectl.cli.system.report import toml_value
from turtlectl.messages.keys import namespace_of
from turtlectl.messages.world import World
from turtlectl.nodes.kinds import KINDS, KindError, kind_of
from turtlectl.runtime.config import NodeConfig
from turtlectl.runtime.params import lookup
from turtlectl.runtime.roles import claims_of, interface_of


class Assignment(msgspec.Struct, frozen=True):
    """``a.b.c = value`` as typed: the dotted key's parts and the value (a TOML value, or
    else the text itself)."""

    text: str
    keys: tuple[str, ...]
    value: Any


def parse_assignment(text: str, option: str, form: str) -> Assignment:
    """``KEY=VALUE``, spaces allowed around both, dots in KEY reaching into tables; VALUE is a
    TOML value (2.5, true, "text", [1, 2]) or else taken as text.  ``form`` is how to write it."""
    key, sep, raw = text.partition("=")
    keys = tuple(part.strip() for part in key.split("."))
    if not sep or not all(keys):
        raise LaunchFileError(f"{option} {text!r}: write it as {form}")
    return Assignment(text=text, keys=keys, value=toml_value(raw.strip()))


def _plan_data(plan: LaunchPlan) -> dict[str, Any]:
    """The plan as launch-file data again (every default filled in), to validate anew."""
    data: dict[str, Any] = msgspec.to_builtins(plan.launch)
    for entry in data["node"]:
        entry["params"] = copy.deepcopy(plan.params[entry["name"]])
    return data


def with_overrides(plan: LaunchPlan, assignments: list[Assignment], option: str) -> LaunchPlan:
    """The plan with each assignment applied and everything validated again, as a file is.

    An assignment's first key names a node (then the rest is a key of its params) or one of
    the tables world, limits, supervisor.  Errors name ``option`` and the node, e.g.
    ``--set navigator.goal_timeot: unknown key; did you mean goal_timeout?``.
    """
    if not assignments:
        return plan
    data = _plan_data(plan)
    names = [e["name"] for e in data["node"]]
    for item in assignments:
        target, *keys = item.keys
        if target in TABLES:
            table = data[target]
        elif target in names:
            table = data["node"][names.index(target)]["params"]
        else:
            tables = ", ".join(TABLES)
            raise LaunchFileError(
                f"{option} {item.text!r}: no node or table named {target!r}{suggestion(target, names + list(TABLES))} "
                f"(nodes: {', '.join(names)}; tables: {tables})"
            )
        if not keys:
            raise LaunchFileError(f"{option} {item.text!r}: name a key of {target}, as {target}.KEY=VALUE")
        _put(table, target, keys, item.value, option)
    changed = validate(data, plan.source, Report(option, list(names), override=True))
    return msgspec.structs.replace(plan, launch=changed.launch, params=changed.params)  # what overrides change


def _put(table: dict[str, Any], target: str, keys: list[str], value: Any, option: str) -> None:
    """Set ``keys`` (dotted into tables, made where missing) of ``target``'s ``table`` to ``value``."""
    for depth, key in enumerate(keys[:-1]):
        table = table.setdefault(key, {})
        if not isinstance(table, dict):
            raise LaunchFileError(f"{option} {'.'.join([target, *keys[: depth + 1]])}: is not a table")
    table[keys[-1]] = value


def launches(kind: str) -> bool:
    """Whether ``kind`` is a built-in kind (the launch file's rules of the whole system then
    apply to ``param set``; a user's own kind is checked by the node alone)."""
    return kind in KINDS


def running_change(
    nodes: dict[str, tuple[str, dict[str, Any]]], world: World, node: str, name: str, text: str, label: str
) -> Any:
    """The value to give ``node``'s parameter ``name`` for ``text`` (a TOML value, else the
    text), validated as ``launch --set`` validates a file, against what runs now: ``nodes``
    (each node's kind and parameters; those of kinds a launch file does not run are left
    out) in ``world``; ``node`` is of a kind it runs.  A rule of the whole system that already
    fails now (a node respawned with its launch file's value may break one) refuses only
    changes that break it differently, so that the change that repairs it, and unrelated
    ones, go through.  LaunchFileError (exit 2) names ``label`` and, when the rule broken is
    about another parameter, that one."""
    nodes = {n: (kind, p) for n, (kind, p) in nodes.items() if launches(kind)}
    data: dict[str, Any] = {
        "world": msgspec.to_builtins(world),
        "node": [
            {"name": n, "namespace": namespace_of(n), "run": kind, "params": copy.deepcopy(p)}
            for n, (kind, p) in nodes.items()
        ],
    }
    names = list(nodes)
    report = Report(label, list(names), override=True)
    assignment = parse_assignment(f"{node}.{name}={text}", label, f"{label} NODE NAME VALUE")
    before = _problem_text(data, report)
    changed = copy.deepcopy(data)
    _put(changed["node"][names.index(node)]["params"], node, list(assignment.keys[1:]), assignment.value, label)
    after = _problem_text(changed, report)
    if after is not None and after != before:
        where = f"{label} {node}.{name}"
        if after.startswith(where) and after[len(where) : len(where) + 1] in (":", "[", "."):
            raise LaunchFileError(after)  # about the value itself (or an item or entry of it)
        rule = after.removeprefix(label + " ")
        raise LaunchFileError(f"{where} = {text}: it would break a rule of the running system: {rule}")
    kind = KINDS[nodes[node][0]]
    typed = msgspec.convert(changed["node"][names.index(node)]["params"], kind.params, strict=True)
    return lookup(msgspec.to_builtins(typed), name)


def _problem_text(data: dict[str, Any], report: Report) -> str | None:
    """The first thing wrong with launch-file ``data`` (as its error reads), or None."""
    try:
        validate(data, report.label, report)
    except LaunchFileError as exc:
        return str(exc)
    return None


#: how to write a ``launch --set`` override
SET_FORM = "NODE.PARAM=VALUE or TABLE.KEY=VALUE (world, limits, supervisor)"


def launch_plan(
    path: Path,
    only: list[str],
    exclude: list[str],
    settings: list[str],
    time_scale: float | None = None,
    arguments: list[str] | None = None,
    use_sim_time: bool = False,
    web: int | None = None,
) -> LaunchPlan:
    """What ``turtlectl launch`` runs: the file at ``path`` with its ``--arg`` values
    (``arguments``), its ``--only``/``--exclude`` selection, then its ``--set`` overrides
    (``settings``), ``--time-scale`` (with_time_scale), ``--use-sim-time`` (with_sim_time) and
    ``--web`` (with_web), all validated as the file is."""
    plan = select_nodes(load_launch(path, arguments), only, exclude)
    plan = with_overrides(plan, [parse_assignment(item, "--set", SET_FORM) for item in settings], "--set")
    plan = plan if time_scale is None else with_time_scale(plan, time_scale)
    plan = with_sim_time(plan) if use_sim_time else plan
    return plan if web is None else with_web(plan, web)


WEB_NODE = "web"


def with_web(plan: LaunchPlan, port: int) -> LaunchPlan:
    """``launch --web PORT``: the plan and a web page node (``run = "web"``) serving on
    127.0.0.1:``port``, as a ``[[node]]`` of the file would; none added when the file runs one
    already (its own port holds)."""
    if any(e.run == WEB_NODE for e in plan.launch.node):
        return plan
    names = {e.name for e in plan.launch.node}
    name = next(n for n in (WEB_NODE, *(f"{WEB_NODE}{i}" for i in range(2, 100))) if n not in names)
    web, named = class_plan(WEB_NODE, [f"port={port}"], Path(plan.folder or "."), name)
    entry = web.launch.node[0]
    return msgspec.structs.replace(
        plan,
        launch=msgspec.structs.replace(plan.launch, node=[*plan.launch.node, entry]),
        params={**plan.params, named: web.params[named]},
        kinds={**plan.kinds, named: web.kinds[named]},
    )


def with_sim_time(plan: LaunchPlan) -> LaunchPlan:
    """``launch --use-sim-time``: every node of the plan follows the ``clock`` key (``use_sim_time``),
    the simulator's or a replay's (``play --clock``) when the plan runs none; a ``cmd`` program is
    not a turtlectl node and keeps its own time.  The simulator, which publishes the clock, runs on
    as it does."""
    nodes = [msgspec.structs.replace(e, use_sim_time=not e.cmd) for e in plan.launch.node]
    return msgspec.structs.replace(plan, launch=msgspec.structs.replace(plan.launch, node=nodes))


def with_time_scale(plan: LaunchPlan, factor: float) -> LaunchPlan:
    """``launch --time-scale F``: the simulator runs ``factor`` times as fast as the wall clock
    (its ``real_time_factor``) and every node of the plan follows its clock (``use_sim_time``;
    a ``cmd`` program is not a turtlectl node and keeps its own time).  Validated as ``--set``."""
    sims = [e.name for e in plan.launch.node if e.run == "sim"]
    plan = with_overrides(
        plan,
        [parse_assignment(f"{name}.real_time_factor={factor!r}", "--time-scale", SET_FORM) for name in sims],
        "--time-scale",
    )
    return with_sim_time(plan)


def class_plan(
    target: str, overrides: list[str], base: Path, name: str | None = None, namespace: str = ""
) -> tuple[LaunchPlan, str]:
    """``turtlectl run module:Class`` (or ``./file.py:Class``, relative to ``base``): a plan of
    that one node, named ``name`` or after its class (``Patrol`` -> ``patrol``), in ``namespace``, with its
    parameters' defaults and ``overrides`` (``KEY=VALUE``), validated as a launch file is
    (LaunchFileError naming ``--param``, or the target when it names no node class); and the
    node's name."""
    try:
        kind = kind_of(target, base)
    except KindError as exc:
        raise LaunchFileError(f"{target}: {exc}") from None
    name = name or _snake(kind.target.rpartition(":")[2])
    data: dict[str, Any] = {"node": [{"name": name, "run": target, "params": {}, "namespace": namespace}]}
    for text in overrides:
        item = parse_assignment(text, "--param", "KEY=VALUE")
        _put(data["node"][0]["params"], name, list(item.keys), item.value, "--param")
    plan = validate(data, target, Report("--param", [name], override=True), base)
    return plan, plan.launch.node[0].name


def _snake(name: str) -> str:
    """``WallFollower`` -> ``wall_follower``: a class's name as a node's."""
    return "".join(f"_{c.lower()}" if c.isupper() and i else c.lower() for i, c in enumerate(name))


def node_config(
    plan: LaunchPlan,
    name: str,
    connect: str,
    overrides: list[str] | None = None,
    domain: str = "",
    log_level: str = "INFO",
) -> NodeConfig:
    """What node ``name`` of ``plan`` is started with; ``overrides`` (``KEY=VALUE`` for its
    params) are validated as the file is (LaunchFileError naming ``--param``)."""
    names = [e.name for e in plan.launch.node]
    if name not in names:
        raise no_node(name, names, plan.source)
    if name in plan.commands:
        raise LaunchFileError(f"{plan.source}: {name} runs a program (cmd), not a turtlectl node: start it yourself")
    if overrides:
        assignments = [parse_assignment(text, "--param", "KEY=VALUE") for text in overrides]
        plan = with_overrides(plan, [msgspec.structs.replace(a, keys=(name, *a.keys)) for a in assignments], "--param")
    entry = plan.launch.node[names.index(name)]
    return NodeConfig(
        name=name,
        kind=entry.run,
        connect=connect,
        domain=domain,
        params=plan.params[name],
        claims=claims_of(name, plan.kinds[name].claims, entry.remap),
        interface=interface_of(name, plan.kinds[name].interface, entry.remap),
        remaps=entry.remap,
        world=plan.launch.world,
        limits=plan.launch.limits,
        log_level=log_level,
        use_sim_time=entry.use_sim_time,
    )


def no_node(name: str, names: list[str], where: str) -> LaunchFileError:
    return LaunchFileError(f"{where}: no node named {name!r}{suggestion(name, names)} (nodes: {', '.join(names)})")


def select_nodes(plan: LaunchPlan, only: list[str], exclude: list[str]) -> LaunchPlan:
    """The plan with just the ``only`` nodes (all if empty), less the ``exclude`` ones; each a
    node selector (cli.selection: a name, a glob such as ``turtle2/*``, a namespace or a turtle,
    ``--only turtle1``: every node that drives turtle1, never the simulator)."""
    names = [e.name for e in plan.launch.node]
    kinds = {e.name: e.run for e in plan.launch.node}
    picked: dict[str, list[str]] = {}
    for option, asked in (("--only", only), ("--exclude", exclude)):
        for name in unmatched(asked, names, kinds):
            raise no_node(name.strip("/"), names, f"{option} {name}")
        picked[option] = selected(asked, names, kinds)
    only, exclude = picked["--only"], picked["--exclude"]
    kept = [e for e in plan.launch.node if (not only or e.name in only) and e.name not in exclude]
    if not kept:
        raise LaunchFileError("--only/--exclude leave no node to run")
    return msgspec.structs.replace(
        plan,
        launch=msgspec.structs.replace(plan.launch, node=kept),
        params={e.name: plan.params[e.name] for e in kept},
        kinds={e.name: plan.kinds[e.name] for e in kept if e.name in plan.kinds},
        commands={e.name: plan.commands[e.name] for e in kept if e.name in plan.commands},
        elsewhere={n: k for n, k in plan.kinds.items() if n not in {e.name for e in kept}},
    )
