"""How a mistake in a launch file reads (pure: no zenoh): ``LaunchFileError``, one line naming
the file (or the chain of files that includes it) and the exact key path, with the node's name
when there is one, e.g. ``launch.toml -> robots/turtle.toml: node[1] (navigator).params.goal_timeot:
unknown key; did you mean goal_timeout?``; or the option of an override, ``--set navigator.rate: ...``.

Used by cli.system.compose (arguments, includes) and cli.system.launchfile (the Structs and
their validation), which re-exports what other modules import.
"""

from __future__ import annotations

import re
from typing import Any

import msgspec
import msgspec.inspect as mi

from turtlectl.cli.errors import BadInput
from turtlectl.runtime.loader import suggestion
from turtlectl.runtime.params import validation_parts


class LaunchFileError(BadInput, ValueError):
    """A launch file (or an override) that cannot be used: bad input; str() is the one-line
    message for the user."""


_FIELD = re.compile(r"^Object (?P<problem>contains unknown|missing required) field `(?P<key>[^`]*)`$")
_PART = re.compile(r"\.([^.\[\]]+)|\[(\d+)\]")

Parts = list[str | int]


def _keys_at(root: type, parts: Parts) -> list[str]:
    """The keys allowed in the table at ``parts`` below ``root`` (empty if unknown)."""
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
            return []
    while isinstance(info, mi.Metadata):
        info = info.type
    return [f.encode_name for f in info.fields] if isinstance(info, mi.StructType) else []


def problem(exc: msgspec.ValidationError, root: Any) -> tuple[Parts, str]:
    """Key path (below ``root``, a type) and what is wrong, from msgspec's message."""
    what, path = validation_parts(exc)
    parts: Parts = [m[1] if m[1] else int(m[2]) for m in _PART.finditer(path)]
    field = _FIELD.match(what)
    if field:
        if field["problem"].startswith("contains"):
            what = "unknown key" + suggestion(field["key"], _keys_at(root, parts))
        else:
            what = "missing required key"
        parts.append(field["key"])
    return parts, what


def raw_names(data: Any) -> list[str | None]:
    """Each [[node]]'s name as written, to name nodes in errors before the file is valid."""
    nodes = data.get("node") if isinstance(data, dict) else None
    if not isinstance(nodes, list):
        return []
    return [n["name"] if isinstance(n, dict) and isinstance(n.get("name"), str) else None for n in nodes]


class Report:
    """Turns a key path into the text users read: ``node[1] (navigator).params.rate`` in a
    file, ``navigator.rate`` for an override of a node's parameter."""

    def __init__(self, label: str, names: list[str | None], override: bool):
        self.label = label  # the file (launch.toml -> robots/turtle.toml when included), or the option (--set)
        self.names = names
        self.override = override
        self.origins: list[str] = []  # where each node of the flattened list is written (group[0].node[1])
        self.files: list[str] = []  # the file (chain) each node of the flattened list is written in, if not label

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
        for part in parts:
            text += f"[{part}]" if isinstance(part, int) else f".{part}"
        return text.lstrip(".")

    def place(self, j: int, i: int) -> str:
        """Where node ``j`` is written, as an error about node ``i`` names it: ``group[0].node[1]``,
        with its file first when that is another (``launch.toml -> turtle.toml: node[0]``)."""
        file = self.files[j] if j < len(self.files) else ""
        same = file == (self.files[i] if i < len(self.files) else "")
        origin = self.origins[j] if j < len(self.origins) else f"node[{j}]"
        return origin if same or not file else f"{file}: {origin}"

    def error(self, parts: Parts, what: str) -> LaunchFileError:
        where = self.where(parts)
        if self.override:
            return LaunchFileError(f"{self.label} {where}: {what}" if where else f"{self.label}: {what}")
        label = self.label
        if len(parts) >= 2 and parts[0] == "node" and isinstance(parts[1], int) and parts[1] < len(self.files):
            label = self.files[parts[1]] or label
        return LaunchFileError(f"{label}: {where}: {what}" if where else f"{label}: {what}")
