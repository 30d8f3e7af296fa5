"""A specification file (TOML), as the capstone's template has it: intent, nodes, interfaces
(topics with their type, publisher and rate; services with their types), success criteria
from a fixed vocabulary of measurable checks, and non-goals.  Pure: parsed and validated
strictly, every error one line naming the file and the key path (SpecError, exit 2)."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Literal

import msgspec

from turtlectl.cli.errors import BadInput
from turtlectl.runtime.params import validation_parts


class SpecError(BadInput):
    """A specification file that cannot be used (exit 2)."""


class _Item(msgspec.Struct, forbid_unknown_fields=True, kw_only=True, frozen=True):
    pass


class NodeSpec(_Item):
    name: str
    purpose: str = ""
    inputs: list[str] = []
    outputs: list[str] = []


class TopicSpec(_Item):
    key: str
    type: str
    publisher: str = ""  # the node that must publish it ("": any)
    period_ms: float | None = None  # its period at a subscriber, when it has one
    tolerance_ms: float = 10.0


class ServiceSpec(_Item):
    key: str
    request: str
    response: str = ""
    server: str = ""  # the node that must serve it ("": any)


class _Check(_Item, tag_field="check"):
    name: str = ""  # how the table calls it (default: made from the check)


class Period(_Check, tag="period", kw_only=True):
    """``key``'s messages come every ``period_ms`` ± ``tolerance_ms`` (ms) for ``share`` of
    ``samples`` periods: as published (``at = "publisher"``: between the messages' own
    ``stamp`` fields, ns, set as each is put; a type without one is timed on arrival) or as they
    arrive at a subscriber here (``at = "subscriber"``: adds the machine's delivery jitter)."""

    key: str
    period_ms: float
    tolerance_ms: float
    samples: int = 50
    share: float = 0.95
    at: Literal["publisher", "subscriber"] = "publisher"


class Goals(_Check, tag="goal", kw_only=True):
    """Each goal (x m, y m, theta degrees) is reached within ``within_s`` of the call, the
    response's pose within ``distance_m`` of it."""

    goals: list[tuple[float, float, float]]
    within_s: float
    distance_m: float


class Messages(_Check, tag="messages", kw_only=True):
    """``count`` messages on ``key`` arrive while every node stays alive (no crash, no respawn)."""

    key: str
    count: int
    within_s: float = 30.0


class ReportedTime(_Check, tag="reported_time", kw_only=True):
    """A goal's reported ``time_taken`` is within ``within_s`` of the client's own clock."""

    goals: list[tuple[float, float, float]]
    within_s: float


Criterion = Period | Goals | Messages | ReportedTime


class Spec(_Item):
    intent: str
    node: list[NodeSpec] = []
    topic: list[TopicSpec] = []
    service: list[ServiceSpec] = []
    criterion: list[Criterion] = []
    non_goals: list[str] = []


def parse_spec(text: str, source: str) -> Spec:
    """The specification in ``text`` (``source``: its file, for messages)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(f"{source}: not valid TOML: {exc}") from None
    try:
        return msgspec.convert(data, Spec, strict=True)
    except msgspec.ValidationError as exc:
        what, path = validation_parts(exc)
        where = path.removeprefix("$").removeprefix(".")
        raise SpecError(f"{source}: {where}: {what}" if where else f"{source}: {what}") from None


def load_spec(path: Path) -> Spec:
    try:
        text = path.read_text()
    except OSError as exc:
        raise SpecError(f"{path}: cannot read: {exc.strerror or exc}") from None
    return parse_spec(text, str(path))


def label(criterion: Criterion) -> str:
    """The criterion as the table names it."""
    if criterion.name:
        return criterion.name
    if isinstance(criterion, Period):
        return f"{criterion.key} every {criterion.period_ms:g} ± {criterion.tolerance_ms:g} ms"
    if isinstance(criterion, Goals):
        return f"{len(criterion.goals)} goals within {criterion.within_s:g} s and {criterion.distance_m:g} m"
    if isinstance(criterion, Messages):
        return f"{criterion.count} messages on {criterion.key}, every node alive"
    return f"time_taken within {criterion.within_s:g} s of the client's clock"
