"""Launch files: TOML, validated completely before anything starts (pure: no zenoh).

A launch file has a ``[world]`` table (size, obstacles), a ``[limits]`` table
(the robot's speed limits) and one ``[[node]]`` table per process.  Every
mistake is reported as ``LaunchFileError`` naming the file and the exact key
path, e.g. ``launch.toml: node[1].params.rate: Expected `float`, got `str```.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path
from typing import Annotated, Any

import msgspec

from nodes.config import NodeConfig
from nodes.kinds import KINDS
from sim.world import Limits, NonNegative, Positive, World

NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_\-]*$")


class LaunchFileError(ValueError):
    """A launch file that cannot be used; str() is the one-line message for the user."""


class NodeEntry(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """One process to run.

    name: unique, letters/digits/_/-.  run: the node kind (see nodes.kinds).
    params: the kind's parameters.
    required: when it exits for good (no respawn, or respawns used up) the system stops, exit code 1.
    respawn: restart it when it exits, first after respawn_delay s, then twice as long each
    time up to respawn_delay_max s; at most respawn_max times in a row (0: no limit).  A
    run longer than STABLE_RUN s counts as healthy and starts the count again.
    """

    name: str
    run: str
    params: dict[str, Any] = msgspec.field(default_factory=dict)
    required: bool = False
    respawn: bool = False
    respawn_delay: NonNegative = 1.0
    respawn_delay_max: NonNegative = 30.0
    respawn_max: Annotated[int, msgspec.Meta(ge=0, le=1_000_000)] = 5


class SupervisorSettings(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """How the supervisor stops the system: SIGINT, wait sigint_timeout s, SIGTERM,
    wait sigterm_timeout s, SIGKILL."""

    sigint_timeout: Positive = 2.0
    sigterm_timeout: Positive = 1.0


class LaunchFile(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    node: list[NodeEntry]
    world: World = msgspec.field(default_factory=World)
    limits: Limits = msgspec.field(default_factory=Limits)
    supervisor: SupervisorSettings = msgspec.field(default_factory=SupervisorSettings)


class LaunchPlan(msgspec.Struct, kw_only=True):
    """A validated launch file: each entry's params already checked against its kind."""

    source: str
    launch: LaunchFile
    params: dict[str, dict[str, Any]]  # node name -> full parameters (defaults filled in)


_AT = re.compile(r"^(?P<what>.*?)(?: - at `\$(?P<path>[^`]*)`)?$", re.S)
_FIELD = re.compile(r"^Object (?P<problem>contains unknown|missing required) field `(?P<key>[^`]*)`$")


def validation_parts(exc: msgspec.ValidationError) -> tuple[str, str]:
    """msgspec's message split into what is wrong and where (``.a.b[0]``, empty at the top)."""
    match = _AT.match(str(exc))
    return (match["what"], match["path"] or "") if match else (str(exc), "")


def _error(source: str, exc: msgspec.ValidationError, prefix: str = "") -> LaunchFileError:
    """One line naming the file and the key path, from msgspec's message."""
    what, path = validation_parts(exc)
    field = _FIELD.match(what)
    if field:
        path += "." + field["key"]
        what = "unknown key" if field["problem"].startswith("contains") else "missing required key"
    path = (prefix + path).lstrip(".")
    return LaunchFileError(f"{source}: {path}: {what}" if path else f"{source}: {what}")


def parse_launch(text: str, source: str = "launch.toml") -> LaunchPlan:
    """Parse and validate launch-file text; ``source`` names it in error messages."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise LaunchFileError(f"{source}: not valid TOML: {exc}") from None
    try:
        launch = msgspec.convert(data, LaunchFile, strict=True)
    except msgspec.ValidationError as exc:
        raise _error(source, exc) from None

    if not launch.node:
        raise LaunchFileError(f"{source}: node: the launch file lists no node")
    seen: set[str] = set()
    params: dict[str, dict[str, Any]] = {}
    for i, entry in enumerate(launch.node):
        where = f"node[{i}]"
        if not NAME_RE.match(entry.name):
            raise LaunchFileError(
                f"{source}: {where}.name: {entry.name!r} is not a valid name (letters, digits, _ and -)"
            )
        if entry.name in seen:
            raise LaunchFileError(f"{source}: {where}.name: duplicate node name {entry.name!r}")
        seen.add(entry.name)
        kind = KINDS.get(entry.run)
        if kind is None:
            known = ", ".join(sorted(KINDS))
            raise LaunchFileError(f"{source}: {where}.run: unknown node kind {entry.run!r} (known: {known})")
        try:
            typed = msgspec.convert(entry.params, kind.params, strict=True)
        except msgspec.ValidationError as exc:
            raise _error(source, exc, prefix=f"{where}.params") from None
        params[entry.name] = msgspec.to_builtins(typed)
    return LaunchPlan(source=source, launch=launch, params=params)


def select_nodes(plan: LaunchPlan, only: list[str], exclude: list[str]) -> LaunchPlan:
    """The plan with just the ``only`` nodes (all if empty), less the ``exclude`` ones."""
    names = [e.name for e in plan.launch.node]
    for option, asked in (("--only", only), ("--exclude", exclude)):
        unknown = [n for n in asked if n not in names]
        if unknown:
            raise LaunchFileError(f"{option}: no node named {', '.join(unknown)} in {plan.source} (nodes: {', '.join(names)})")
    kept = [e for e in plan.launch.node if (not only or e.name in only) and e.name not in exclude]
    if not kept:
        raise LaunchFileError("--only/--exclude leave no node to run")
    launch = msgspec.structs.replace(plan.launch, node=kept)
    return LaunchPlan(source=plan.source, launch=launch, params={e.name: plan.params[e.name] for e in kept})


def with_params(plan: LaunchPlan, name: str, params: dict[str, Any], option: str) -> LaunchPlan:
    """The plan with node ``name``'s params replaced by ``params``, validated as the file's are
    (errors name ``option``, e.g. ``--set navigator``)."""
    entry = next((e for e in plan.launch.node if e.name == name), None)
    if entry is None:
        known = ", ".join(e.name for e in plan.launch.node)
        raise LaunchFileError(f"{option}: no node named {name!r} (nodes: {known})")
    try:
        typed = msgspec.convert(params, KINDS[entry.run].params, strict=True)
    except msgspec.ValidationError as exc:
        raise _error(option, exc) from None
    return LaunchPlan(source=plan.source, launch=plan.launch, params={**plan.params, name: msgspec.to_builtins(typed)})


def node_config(
    plan: LaunchPlan, name: str, connect: str, overrides: dict[str, Any] | None = None, domain: str = ""
) -> NodeConfig:
    """What node ``name`` of ``plan`` is started with; ``overrides`` replace its params and
    are validated as the file's are (LaunchFileError naming ``--param``)."""
    entry = next((e for e in plan.launch.node if e.name == name), None)
    if entry is None:
        known = ", ".join(e.name for e in plan.launch.node)
        raise LaunchFileError(f"{plan.source}: no node named {name!r} (nodes: {known})")
    if overrides is not None:
        plan = with_params(plan, name, overrides, "--param")
    params = plan.params[name]
    return NodeConfig(
        name=name,
        kind=entry.run,
        connect=connect,
        domain=domain,
        params=params,
        world=plan.launch.world,
        limits=plan.launch.limits,
    )


def load_launch(path: Path) -> LaunchPlan:
    """Read and validate a launch file from disk."""
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise LaunchFileError(f"{path}: cannot read: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise LaunchFileError(f"{path}: not UTF-8 text") from None
    return parse_launch(text, source=str(path))
