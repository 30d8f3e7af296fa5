"""How a mistake in a launch file reads (pure: no zenoh): ``LaunchFileError``, one line naming
the file (or the chain of files that includes it) and the exact key path, with the node's name
when there is one, e.g. ``launch.toml -> include[0] robots/turtle.toml: node[1] (navigator).params.goal_timeot:
unknown key; did you mean goal_timeout?``; or the option of an override, ``--set navigator.rate: ...``.

Used by cli.system.compose (arguments, includes) and cli.system.launchfile (the Structs and
their validation), which re-exports what other modules import.
"""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path
from typing import Any

import msgspec
import msgspec.inspect as mi

from turtlectl.runtime.client.errors import BadInput
from turtlectl.runtime.loader import suggestion
from turtlectl.runtime.params import got, in_words, validation_parts


class LaunchFileError(BadInput, ValueError):
    """A launch file (or an override) that cannot be used: bad input; str() is the one-line
    message for the user."""


_FIELD = re.compile(r"^Object (?P<problem>contains unknown|missing required) field `(?P<key>[^`]*)`$")
_PART = re.compile(r"\.([^.\[\]]+)|\[(\d+)\]")

Parts = list[str | int]
_NONE: Any = object()  # no data given to ``problem``


def _type_at(root: type, parts: Parts) -> Any:
    """msgspec's type info of the value at ``parts`` below ``root``, metadata unwrapped (None if unknown)."""
    info: Any = mi.type_info(root)
    for part in parts:
        while isinstance(info, mi.Metadata):
            info = info.type
        if isinstance(part, int) and isinstance(info, mi.ListType):
            info = info.item_type
        elif isinstance(part, str) and isinstance(info, mi.StructType):
            info = next((f.type for f in info.fields if f.encode_name == part), None)
        elif isinstance(part, str) and isinstance(info, mi.DictType):
            info = info.value_type
        else:
            return None
    while isinstance(info, mi.Metadata):
        info = info.type
    return info


def _keys_at(root: type, parts: Parts) -> list[str]:
    """The keys allowed in the table at ``parts`` below ``root`` (empty if unknown)."""
    info = _type_at(root, parts)
    return [f.encode_name for f in info.fields] if isinstance(info, mi.StructType) else []


def problem(exc: msgspec.ValidationError, root: Any, data: Any = _NONE) -> tuple[Parts, str]:
    """Key path (below ``root``, a type) and what is wrong, from msgspec's message; a value of the
    wrong type or out of range in the words `param set` uses (``must be a number (got "fast")``,
    runtime.params.in_words), with the value from ``data`` (what was validated) when given."""
    what, path = validation_parts(exc)
    parts: Parts = [m[1] if m[1] else int(m[2]) for m in _PART.finditer(path)]
    field = _FIELD.match(what)
    if field:
        if field["problem"].startswith("contains"):
            what = "unknown key" + suggestion(field["key"], _keys_at(root, parts))
        else:
            what = "missing required key"
        parts.append(field["key"])
    elif words := in_words(what):
        what = words + _given(data, parts)
    elif what.startswith("Invalid enum value") and isinstance(info := _type_at(root, parts), mi.LiteralType):
        what = "must be one of " + ", ".join(map(str, info.values)) + _given(data, parts)
    return parts, what


def _given(data: Any, parts: Parts) -> str:
    """`` (got VALUE)`` for the value at ``parts`` in ``data``; "" if there is none."""
    for part in parts:
        try:
            data = data[part]
        except (KeyError, IndexError, TypeError):
            return ""
    return "" if data is _NONE else got(data)


def raw_names(data: Any) -> list[str | None]:
    """Each [[node]]'s name as written, to name nodes in errors before the file is valid."""
    nodes = data.get("node") if isinstance(data, dict) else None
    if not isinstance(nodes, list):
        return []
    return [n["name"] if isinstance(n, dict) and isinstance(n.get("name"), str) else None for n in nodes]


def key_path(parts: Parts) -> str:
    """A key path as errors write it: ``node[1].params.rate`` (a text part as it is, an index in [])."""
    return "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in parts).lstrip(".")


def toml_value(text: str) -> Any:
    """``text`` as a TOML value (2.5, true, "text", [1, 2]), or else the text itself."""
    try:
        document = tomllib.loads(f"v = {text}")
    except tomllib.TOMLDecodeError:
        return text
    return document["v"] if len(document) == 1 else text


class Report:
    """Turns a key path into the text users read: ``node[1] (navigator).params.rate`` in a
    file, ``navigator.rate`` for an override of a node's parameter."""

    def __init__(self, label: str, names: list[str | None], override: bool):
        self.label = label  # the file (launch.toml -> robots/turtle.toml when included), or the option (--set)
        self.names = names
        self.override = override
        self.origins: list[str] = []  # where each node of the flattened list is written (group[0].node[1])
        self.files: list[str] = []  # the file (chain) each node of the flattened list is written in, if not label
        self.sources: dict[str, str] = {}  # key path in the file -> where its value came from (an argument)
        self.node_sources: list[dict[str, str]] = []  # the same for the file of each node of the flattened list

    def where(self, parts: Parts) -> str:
        text = ""
        if len(parts) >= 2 and parts[0] == "node" and isinstance(parts[1], int):
            i, rest = parts[1], parts[2:]
            name = self.names[i] if i < len(self.names) else None
            if self.override and name and rest[:1] == ["params"]:
                text, rest = name, rest[1:]
            else:
                origin = self.origins[i] if i < len(self.origins) else f"node[{i}]"
                text = origin + (f" ({name})" if name else "")
            parts = rest
        return key_path([text, *parts] if text else parts)

    def place(self, j: int, i: int) -> str:
        """Where node ``j`` is written, as an error about node ``i`` names it: ``group[0].node[1]``,
        with its file first when that is another (``launch.toml -> turtle.toml: node[0]``)."""
        file = self.files[j] if j < len(self.files) else ""
        same = file == (self.files[i] if i < len(self.files) else "")
        origin = self.origins[j] if j < len(self.origins) else f"node[{j}]"
        return origin if same or not file else f"{file}: {origin}"

    def source(self, parts: Parts) -> str:
        """`` (from --arg speed through include[0].args.max_speed)`` when the value at ``parts`` was
        an argument's, else ``""``."""
        sources, local = self.sources, parts
        if len(parts) >= 2 and parts[0] == "node" and isinstance(parts[1], int) and parts[1] < len(self.origins):
            i = parts[1]
            sources = self.node_sources[i] if i < len(self.node_sources) else {}
            local = [self.origins[i], *parts[2:]]
        for n in range(len(local), 0, -1):  # the value, else the table that holds it
            key = key_path(local[:n])
            if key in sources:
                return f" (from {sources[key]})"
        return ""

    def error(self, parts: Parts, what: str) -> LaunchFileError:
        where = self.where(parts)
        what += self.source(parts)
        sep = " " if what.startswith("must ") else ": "  # a sentence: "goal_timeout must be a number"
        if self.override:
            return LaunchFileError(f"{self.label} {where}{sep}{what}" if where else f"{self.label}: {what}")
        label = self.label
        if len(parts) >= 2 and parts[0] == "node" and isinstance(parts[1], int) and parts[1] < len(self.files):
            label = self.files[parts[1]] or label
        return LaunchFileError(f"{label}: {where}{sep}{what}" if where else f"{label}: {what}")


def positional_arg_problem(file: Path | None, extra: list[str]) -> str | None:
    """What is wrong with ``launch FILE EXTRA...`` (None: nothing): ROS's positional ``speed:=2``
    is ``--arg speed:=2`` here (as FILE too, when it is no file)."""
    written = [str(file)] if file is not None and ("=" in file.name and not file.exists()) else []
    for item in [*written, *extra]:
        if "=" in item:
            return f"{item}: give launch arguments as --arg {item}"
        return f"{item}: launch takes one FILE (arguments: --arg NAME=VALUE)"
    return None


def toml_text(value: Any) -> str:
    """``value`` as TOML writes it: true, "fast", 2.5, [1, 2], { a = 1 }."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(toml_text(item) for item in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {toml_text(v)}" for k, v in value.items()) + " }" if value else "{}"
    return repr(value)


def declared_below(name: str, includes: Any, path: Path, seen: tuple[Path, ...] = ()) -> str | None:
    """The file, among those ``includes`` (a file's raw ``[[include]]`` list) bring, that declares
    argument ``name``, as ``robots/robot.toml (include[0])``; None: none does (or they cannot be read)."""
    if not isinstance(includes, list):
        return None
    for i, include in enumerate(includes):
        file = include.get("file") if isinstance(include, dict) else None
        if not isinstance(file, str) or "$(" in file:
            continue
        target = (path.parent / Path(file).expanduser()).resolve()
        if target in seen or not target.is_file():
            continue
        try:
            data = tomllib.loads(target.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
            continue
        if isinstance(data.get("arg"), dict) and name in data["arg"]:
            return f"{file} (include[{i}])"
        deeper = declared_below(name, data.get("include"), target, (*seen, target))
        if deeper:
            return f"{deeper.rpartition(' (')[0]} (include[{i}] {file} -> {deeper.rpartition(' (')[2]}"
    return None


def read_text(path: Path, label: str) -> str:
    """A launch file's text (LaunchFileError naming ``label``, the file or its chain of includes,
    when it cannot be read or is not UTF-8)."""
    try:
        return path.read_text(encoding="utf-8")
    except OSError as exc:
        raise LaunchFileError(f"{label}: cannot read: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise LaunchFileError(f"{label}: not UTF-8 text") from None
