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
from typing import Any

import msgspec

from nodes.config import NodeConfig
from nodes.kinds import KINDS
from sim.world import Limits, NonNegative, World

NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_\-]*$")


class LaunchFileError(ValueError):
    """A launch file that cannot be used; str() is the one-line message for the user."""


class NodeEntry(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """One process to run.

    name: unique, letters/digits/_/-.  run: the node kind (see nodes.kinds).
    params: the kind's parameters.  required: its exit stops the system.
    respawn: restart it when it exits, after respawn_delay s.
    """

    name: str
    run: str
    params: dict[str, Any] = msgspec.field(default_factory=dict)
    required: bool = False
    respawn: bool = False
    respawn_delay: NonNegative = 1.0


class LaunchFile(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    node: list[NodeEntry]
    world: World = msgspec.field(default_factory=World)
    limits: Limits = msgspec.field(default_factory=Limits)


class LaunchPlan(msgspec.Struct, kw_only=True):
    """A validated launch file: each entry's params already checked against its kind."""

    source: str
    launch: LaunchFile
    params: dict[str, dict[str, Any]]  # node name -> full parameters (defaults filled in)


_AT = re.compile(r"^(?P<what>.*?)(?: - at `\$(?P<path>[^`]*)`)?$", re.S)
_FIELD = re.compile(r"^Object (?P<problem>contains unknown|missing required) field `(?P<key>[^`]*)`$")


def _error(source: str, exc: msgspec.ValidationError, prefix: str = "") -> LaunchFileError:
    """One line naming the file and the key path, from msgspec's message."""
    match = _AT.match(str(exc))
    what, path = (match["what"], match["path"] or "") if match else (str(exc), "")
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


def node_config(plan: LaunchPlan, name: str, connect: str, overrides: dict[str, Any] | None = None) -> NodeConfig:
    """What node ``name`` of ``plan`` is started with; ``overrides`` replace its params and
    are validated as the file's are (LaunchFileError naming ``--param``)."""
    entry = next((e for e in plan.launch.node if e.name == name), None)
    if entry is None:
        known = ", ".join(e.name for e in plan.launch.node)
        raise LaunchFileError(f"{plan.source}: no node named {name!r} (nodes: {known})")
    params = plan.params[name]
    if overrides is not None:
        try:
            params = msgspec.to_builtins(msgspec.convert(overrides, KINDS[entry.run].params, strict=True))
        except msgspec.ValidationError as exc:
            raise _error("--param", exc) from None
    return NodeConfig(
        name=name,
        kind=entry.run,
        connect=connect,
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
