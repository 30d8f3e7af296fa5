"""``turtlectl plot``'s model (pure: no Zenoh, no terminal, no files, nothing printed).

- ``parse_series``: what a user types, ``KEY.FIELD`` (``robot/status.battery``), as a ``Series``:
  the key (resolved for ``--turtle`` as echo's TOPIC is) and the field's dotted path.  The key is
  everything up to the first ``.`` of its last chunk (after the last ``/``); the rest is the path,
  nested fields and list items as echo's ``--field`` writes them (``obstacles.ranges.0``,
  ``navigate_to/feedback.path.0.1``).  A key whose last chunk has a ``.`` of its own cannot be
  plotted; a key with a wildcard neither (one key per series).
- ``Extractor``: the number a message holds at a series' path (a bool is 0 or 1; inf and NaN
  are no sample).  The first message of a series must have a number there, else BadInput (exit 2)
  naming the numeric fields its type has; after that a message without one is left out (a list
  that is shorter this time).  ``check_type`` says the same before any message, for a type
  known in advance (a built-in key's).
- ``Stamps``: --stamps' time axis, each message's own ``stamp`` (s from the first);
  ``nearest_key``: the built-in key a typo was meant to be.
- The sliding window of the live plot, its status line and the samples collected whole: in
  ``cli.tools.plot_window``.
- ``picture_format``: ``--output``'s file type from its extension (png or svg).
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import msgspec
import msgspec.inspect as mi

from turtlectl.cli.tools.format import Undescribed
from turtlectl.messages import Message
from turtlectl.messages.codec import type_name as full_type_name
from turtlectl.messages.keys import TOPICS, resolve
from turtlectl.runtime.client.errors import BadInput

#: the file types ``--output`` writes, by extension
PICTURE_FORMATS = ("png", "svg")
#: what ``numeric_fields`` writes for "any index of this list"
ANY_INDEX = "N"
#: the field --stamps reads each message's time from (ns since the epoch)
STAMP = "stamp"


@dataclasses.dataclass(frozen=True)
class Series:
    """One line of the plot: the numbers at ``path`` in the messages on ``key``."""

    key: str
    path: str

    @property
    def label(self) -> str:
        """How the plot names it: ``robot/status.battery`` (the key as resolved for --turtle)."""
        return f"{self.key}.{self.path}"


def parse_series(text: str, turtle: str = "") -> Series:
    """``KEY.FIELD`` as typed (``robot/status.battery``, ``turtle1/pose.x``, ``obstacles.ranges.0``);
    ``turtle``: --turtle's namespace (``turtle2``: ``robot/status`` is ``turtle2/robot/status``).
    BadInput for anything else, with the way to write it."""
    head, slash, last = text.rpartition("/")
    name, dot, path = last.partition(".")
    key = f"{head}{slash}{name}"
    if not dot:
        known = head and last and builtin_anywhere(resolve(head, turtle), turtle) is not None
        hint = f"{head}.{last}" if known else "robot/status.battery"  # rqt_plot's turtle1/pose/x, any turtle's
        raise BadInput(f"{text!r}: name a field after the key and a '.', as {hint} (KEY.FIELD)")
    if not key.strip("/") or not path:
        raise BadInput(f"{text!r}: write KEY.FIELD, as robot/status.battery or turtle1/pose.x")
    if any(not part for part in path.split(".")):
        raise BadInput(
            f"{text!r}: the field {path!r} has an empty part (write nested fields as a.b, items as ranges.0)"
        )
    if any(c in key for c in "*$?#") or key.lstrip("/").startswith("@") or "//" in key or key.endswith("/"):
        raise BadInput(f"{text!r}: plot one plain key per series (no wildcards, nothing starting with '@')")
    return Series(resolve(key, turtle), path)


def parse_all(texts: Iterable[str], turtle: str = "") -> list[Series]:
    """Every series typed, each once, in the order typed.  A recording typed as a series (``plot
    run.mcap robot/status.battery`` reads as key ``run``, field ``mcap``) is BadInput saying to
    use --input."""
    texts = list(texts)
    for text in texts:
        recording = text.endswith(".mcap")
        if recording or Path(text).is_file():
            rest = [t for t in texts if t != text and not t.endswith(".mcap")] or ["robot/status.battery"]
            what = "a recording" if recording else "a file"
            how = "plot it with --input" if recording else "plot a recording with --input"
            raise BadInput(f"{text} is {what}, not KEY.FIELD: {how}, as turtlectl plot {' '.join(rest)} --input {text}")
    return list(dict.fromkeys(parse_series(text, turtle) for text in texts))


def number(value: Any) -> float | None:
    """``value`` as a number to plot: a bool is 0 or 1 (an int); None for anything else (text, lists)."""
    if isinstance(value, int | float):
        return float(value)
    return None


class _Missing(Exception):
    """No value at a path (no such field, an index out of range)."""


class _PastTheEnd(_Missing):
    """An index past the end of a list: ``at`` (the list's path), its ``length``, the ``index``."""

    def __init__(self, at: str, length: int, index: str):
        super().__init__(at)
        self.at, self.length, self.index = at, length, index


def _data(message: Any) -> Any:
    """What a message's fields are read from: an undescribed payload's data, a message itself
    (a described type's own field named ``data`` is one of its fields)."""
    return message.data if isinstance(message, Undescribed) else message


def value_at(message: Any, path: str) -> Any:
    """The value at dotted ``path`` in a message (a Struct) or undescribed data (dicts, lists):
    fields by name, list items by index (negative from the end); _Missing if there is none."""
    value = message
    for depth, part in enumerate(path.split(".")):
        if isinstance(value, msgspec.Struct) and part in value.__struct_fields__:
            value = getattr(value, part)
        elif isinstance(value, dict) and part in value:
            value = value[part]
        elif isinstance(value, list | tuple) and part.lstrip("-").isdigit():
            index = int(part)
            if not -len(value) <= index < len(value):
                at = ".".join(path.split(".")[:depth])
                raise _PastTheEnd(at, len(value), _join(at, part))
            value = value[index]
        else:
            raise _Missing(path)
    return value


def type_name(message: Any) -> str:
    """The name of a message's type for people: its full name (``turtlectl/Pose``), or an
    undescribed payload's own."""
    if isinstance(message, Message):
        return full_type_name(type(message))
    name = getattr(message, "type_name", "")  # an Undescribed's (its payload's "type" if it had no other)
    return str(name) if name else "the payload"


def _type_paths(info: Any, prefix: str) -> list[str]:
    """The numeric paths of a msgspec type (``msgspec.inspect``), under ``prefix``."""
    if isinstance(info, mi.UnionType):  # Optional[X]: X's
        return [p for t in info.types if not isinstance(t, mi.NoneType) for p in _type_paths(t, prefix)]
    if isinstance(info, mi.FloatType | mi.IntType | mi.BoolType):
        return [prefix]
    if isinstance(info, mi.EnumType) and issubclass(info.cls, int):
        return [prefix]
    if isinstance(info, mi.StructType):
        return [p for f in info.fields if f.name != "type" for p in _type_paths(f.type, _join(prefix, f.name))]
    if isinstance(info, mi.ListType | mi.VarTupleType | mi.SetType | mi.FrozenSetType):
        return _type_paths(info.item_type, _join(prefix, ANY_INDEX))
    if isinstance(info, mi.TupleType):
        return [p for i, t in enumerate(info.item_types) for p in _type_paths(t, _join(prefix, str(i)))]
    return []


def _data_paths(value: Any, prefix: str) -> list[str]:
    """The numeric paths of undescribed data, plain data as decoded (a list's by its first item)."""
    if number(value) is not None:
        return [prefix]
    if isinstance(value, dict):
        return [p for k, v in value.items() if prefix or k != "type" for p in _data_paths(v, _join(prefix, str(k)))]
    if isinstance(value, list | tuple) and value:
        return _data_paths(value[0], _join(prefix, ANY_INDEX))
    return []


def _join(prefix: str, part: str) -> str:
    return f"{prefix}.{part}" if prefix else part


def numeric_fields(message: Any) -> list[str]:
    """The paths a message's type has numbers at (``ranges.N``: any item of a list), as
    ``parse_series`` reads them after the key."""
    if isinstance(message, msgspec.Struct):
        return _type_paths(mi.type_info(type(message)), "")
    return _data_paths(_data(message), "")


def _no_number(series: Series, name: str, fields: list[str], why: str) -> BadInput:
    listed = ", ".join(fields) if fields else "none"
    return BadInput(f"{series.label}: {why}; the numeric fields of {name}: {listed}")


def _kind(value: Any, label: str) -> str:
    """What ``value`` is, when it is no number, and what to plot instead."""
    if isinstance(value, str):
        return f"text ({value!r}), not a number"
    if isinstance(value, list | tuple):
        return f"a list of {len(value)}: plot one of its items, as {label}.0"
    if isinstance(value, dict | msgspec.Struct):
        return f"a table of fields: plot one of them, as {label}.NAME"
    return f"{type(value).__name__} ({value!r}), not a number"


def check(series: Series, message: Any) -> float | None:
    """The number ``message`` holds for ``series`` (None for inf or NaN: no sample); BadInput
    if it holds none there, naming the numeric fields its type has."""
    try:
        value = value_at(_data(message), series.path)
    except _PastTheEnd as past:
        items = f"{past.length} item{'s' * (past.length != 1)}"
        raise BadInput(
            f"{series.label}: {series.key}.{past.at} has {items} in the first {type_name(message)}; "
            f"{past.index} is past the end ({past.at}.-1 is the last)"
        ) from None
    except _Missing:
        why = f"{type_name(message)} has no field {series.path!r}"
        raise _no_number(series, type_name(message), numeric_fields(message), why) from None
    found = number(value)
    if found is None:
        why = f"{series.path} is {_kind(value, series.label)}"
        raise _no_number(series, type_name(message), numeric_fields(message), why)
    return found if math.isfinite(found) else None


def check_type(series: Series, msg_type: type[Message]) -> None:
    """Before any message: BadInput if messages of ``msg_type`` can have no number at
    ``series.path`` (no such field, or one that is not a number), naming the ones they have.
    Indexes are not checked (a list's length is the message's)."""
    fields = _type_paths(mi.type_info(msg_type), "")
    wanted = series.path.split(".")
    if any(_matches(candidate, wanted) for candidate in fields):
        return
    name = full_type_name(msg_type)
    below = [p for p in fields if len(p.split(".")) > len(wanted) and _matches(_head(p, len(wanted)), wanted)]
    first = series.path.split(".")[0]
    if first not in {f.name for f in mi.type_info(msg_type).fields}:
        why = f"{name} has no field {first!r}"
    elif below:
        example = ".".join("0" if part == ANY_INDEX else part for part in below[0].split("."))
        why = f"{series.path} holds several values: plot one number of it, as {series.key}.{example}"
    else:
        why = f"{series.path} is not a number"
    raise _no_number(series, name, fields, why)


def _head(path: str, parts: int) -> str:
    return ".".join(path.split(".")[:parts])


def _matches(candidate: str, wanted: list[str]) -> bool:
    """A numeric path of a type (``ranges.N``) read as the path typed (``ranges.3``, split)."""
    parts = candidate.split(".")
    return len(parts) == len(wanted) and all(
        a == b or (b == ANY_INDEX and a.lstrip("-").isdigit()) for a, b in zip(wanted, parts, strict=True)
    )


def builtin_type(key: str, turtle: str = "") -> type[Message] | None:
    """The type a built-in topic carries (``robot/status``: TurtleStatus), as resolved for
    --turtle (``turtle2/robot/status`` with turtle2); None for any other key (a user's own)."""
    for known, msg_type in TOPICS.items():
        if resolve(known, turtle) == key:
            return msg_type
    return None


def builtin_anywhere(key: str, turtle: str = "") -> type[Message] | None:
    """``builtin_type`` of ``key`` for --turtle, or in the namespace its first part names
    (``turtle2/pose``, ``turtle3/robot/status``: any turtle's built-in topics, typed whole)."""
    return builtin_type(key, turtle) or builtin_type(key, key.partition("/")[0])


def check_builtins(
    series: list[Series], turtle: str = "", stamps: bool = False, types: dict[str, type[Message]] | None = None
) -> None:
    """``check_type`` for each series on a built-in key (its type known before any message):
    a typo says so at once, before anything is drawn or waited for; with ``stamps``
    (--stamps), BadInput naming the types that have no stamp (also those of ``types``,
    key -> type: a recording's)."""
    known = dict(types or {})
    for s in series:
        msg_type = builtin_type(s.key, turtle)
        if msg_type is not None:
            check_type(s, msg_type)
            known[s.key] = msg_type
    if stamps:
        check_stamped(known)


def check_stamped(types: dict[str, type[Message]]) -> None:
    """--stamps: BadInput naming the types (key -> type) that have no stamp."""
    unstamped = [f"{full_type_name(t)} on {key}" for key, t in types.items() if STAMP not in t.__struct_fields__]
    if unstamped:
        raise _unstamped(unstamped)


def _unstamped(which: list[str]) -> BadInput:
    return BadInput(
        f"--stamps: {', '.join(dict.fromkeys(which))} has no stamp: plot it without --stamps "
        "(the time axis is then when each message arrived)"
    )


def nearest_key(key: str, turtle: str = "") -> str | None:
    """The built-in key (as resolved for --turtle) nearest to ``key``, a typo's
    (``turtle1/pos``: ``turtle1/pose``); None for a built-in key or one near none."""
    known = [resolve(k, turtle) for k in TOPICS]
    if key in known:
        return None
    near = difflib.get_close_matches(key, known, n=1, cutoff=0.75)
    return near[0] if near else None


class Stamps:
    """--stamps' time axis: each message's own ``stamp`` (ns since the epoch: simulated time in a
    system run with --time-scale) in s from the first stamp seen."""

    def __init__(self) -> None:
        self.origin: int | None = None

    def time(self, key: str, message: Any) -> float | None:
        """When ``message`` (on ``key``) was stamped, s from the first stamp; None for one not
        stamped (0); BadInput for a message whose type has no stamp."""
        try:
            stamp = value_at(_data(message), STAMP)
        except _Missing:
            raise _unstamped([f"{type_name(message)} on {key}"]) from None
        if isinstance(stamp, bool) or not isinstance(stamp, int | float) or stamp <= 0:
            return None
        if self.origin is None:
            self.origin = int(stamp)
        return (stamp - self.origin) / 1e9


class Extractor:
    """The numbers of each series, message after message: the first message of a series is
    ``check``ed (BadInput if it has no number there); later ones without one are skipped."""

    def __init__(self, series: list[Series]):
        self.series = series
        self.by_key: dict[str, list[Series]] = {}
        for s in series:
            self.by_key.setdefault(s.key, []).append(s)
        self.seen: set[Series] = set()

    def values(self, key: str, message: Any) -> list[tuple[Series, float]]:
        """The samples one message on ``key`` gives: (series, number) for each series it fits."""
        found = []
        data = _data(message)
        for s in self.by_key.get(key, ()):
            if s in self.seen:
                try:
                    value = number(value_at(data, s.path))
                except _Missing:
                    continue
                if value is None or not math.isfinite(value):
                    continue
            else:
                value = check(s, message)
                self.seen.add(s)
                if value is None:
                    continue
            found.append((s, value))
        return found


def picture_format(path: Path) -> str:
    """``--output``'s file type: ``png`` or ``svg`` from its extension (any case); BadInput otherwise."""
    suffix = path.suffix.lower().lstrip(".")
    if suffix not in PICTURE_FORMATS:
        given = f"{path.suffix!r}" if path.suffix else "no extension"
        raise BadInput(f"--output {str(path)!r}: write a .png or .svg file ({given} is neither)")
    return suffix
