"""A specification file (TOML), as the capstone's template has it: intent, nodes, interfaces
(topics with their type, publisher and rate; services with their types), success criteria
from a fixed vocabulary of measurable checks, and non-goals.  Pure: parsed and validated
strictly, every error one line naming the file and the key path (SpecError, exit 2)."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Annotated, Any, Literal

import msgspec

from turtlectl.runtime.client.errors import BadInput
from turtlectl.runtime.loader import suggestion
from turtlectl.runtime.params import validation_parts


class SpecError(BadInput):
    """A specification file that cannot be used (exit 2)."""


# the ranges a value may take (a share of 95 meant as 95 %, a NaN, a negative time: refused by name)
Ms = Annotated[float, msgspec.Meta(gt=0.0, le=3_600_000.0)]  # a period, ms
ToleranceMs = Annotated[float, msgspec.Meta(ge=0.0, le=3_600_000.0)]
Seconds = Annotated[float, msgspec.Meta(gt=0.0, le=86_400.0)]
Metres = Annotated[float, msgspec.Meta(gt=0.0, le=1_000_000.0)]
Degrees = Annotated[float, msgspec.Meta(gt=0.0, le=180.0)]
Minutes = Annotated[float, msgspec.Meta(gt=0.0, le=10_080.0)]
Count = Annotated[int, msgspec.Meta(ge=1, le=1_000_000)]
Share = Annotated[float, msgspec.Meta(gt=0.0, le=1.0)]  # a fraction: 0.95, not 95
Coordinate = Annotated[float, msgspec.Meta(ge=-1_000_000.0, le=1_000_000.0)]  # m or degrees, finite


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
    period_ms: Ms | None = None  # its mean published period, ms, when it has one
    tolerance_ms: ToleranceMs = 10.0


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
    period_ms: Ms
    tolerance_ms: ToleranceMs
    samples: Count = 50
    share: Share = 0.95
    at: Literal["publisher", "subscriber"] = "publisher"


Pose = tuple[Coordinate, Coordinate, Coordinate]


class Goals(_Check, tag="goal", kw_only=True):
    """Each goal (x m, y m, theta degrees) is reached within ``within_s`` of the call, the
    response's pose within ``distance_m`` of it (and, with ``heading_deg``, its heading within
    that many degrees).  ``start``: the turtle is teleported there (x m, y m, theta degrees)
    before each goal.  ``random``: that many more goals drawn with ``seed`` in ``area``
    (x_min, y_min, x_max, y_max, m; the same goals for the same seed)."""

    goals: list[Pose] = []
    within_s: Seconds
    distance_m: Metres
    heading_deg: Degrees | None = None
    start: Pose | None = None
    random: Annotated[int, msgspec.Meta(ge=0, le=10_000)] = 0
    seed: int = 0
    area: tuple[Coordinate, Coordinate, Coordinate, Coordinate] = (1.0, 1.0, 10.0, 10.0)


class Messages(_Check, tag="messages", kw_only=True):
    """``count`` messages on ``key`` arrive while every node stays alive (no crash, no respawn)."""

    key: str
    count: Count
    within_s: Seconds = 30.0


class ReportedTime(_Check, tag="reported_time", kw_only=True):
    """A goal's reported ``time_taken`` is within ``within_s`` of the client's own clock."""

    goals: Annotated[list[Pose], msgspec.Meta(min_length=1)]
    within_s: Seconds


class NoErrors(_Check, tag="no_errors", kw_only=True):
    """``node`` (every node when empty) runs ``minutes`` without errors: alive throughout, the
    same process (no crash, no respawn), and no log record at ERROR or worse meanwhile.  A long
    one: ``verify --short S`` runs it S seconds, and the table says so.

    Meanwhile goals are driven one after another through ``navigate_to``: ``goals`` (x m, y m,
    theta degrees) in turn, over again, or with ``random_goals`` goals drawn with ``seed`` in the
    world the simulator declares, clear of its walls and obstacles.  A goal that ends unreached
    (refused, blocked, timed out) is counted, not failed; a goal whose call errs (no navigator,
    no answer, a cancel nobody confirms) fails the criterion."""

    node: str = ""
    minutes: Minutes
    goals: list[Pose] = []
    random_goals: bool = False
    seed: int = 0


class Parameters(_Check, tag="parameters", kw_only=True):
    """Each node runs with the parameters it was meant to: every node of the launch file (the
    one ``verify --launch`` starts, or ``verify --launch-file`` names for a system already
    running) runs, with the launch file's ``run`` as its kind, and its parameters equal the
    launch file's (defaults filled in, as ``launch`` validates them); and each node in
    ``params`` runs with those values (``{ navigator = { goal_timeout = 30.0 } }``: the keys
    given, a table's too).  Read as ``turtlectl param dump`` reads them."""

    params: dict[
        str, Any
    ] = {}  # node -> {parameter: value} (a table: a dict of its keys); parse_spec checks each names the node


class RoundTrip(_Check, tag="round_trip", kw_only=True):
    """Every message type on ``keys`` (every published topic when empty) round-trips: a live
    message decodes strictly as its described type, and encoding it and decoding it again gives
    the same message.  Each key must have a message within ``within_s``."""

    keys: list[str] = []
    within_s: Seconds = 5.0


Criterion = Period | Goals | Messages | ReportedTime | NoErrors | RoundTrip | Parameters
#: each check by its name in a spec file
CHECKS: dict[str, type[_Check]] = {
    c.__struct_config__.tag: c  # type: ignore[misc]
    for c in (Period, Goals, Messages, ReportedTime, NoErrors, RoundTrip, Parameters)
}


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
        spec = msgspec.convert(data, Spec, strict=True)
    except msgspec.ValidationError as exc:
        what, path = validation_parts(exc)
        where = path.removeprefix("$").removeprefix(".")
        what += _hint(what, where, data)
        raise SpecError(f"{source}: {where}: {what}" if where else f"{source}: {what}") from None
    named: dict[str, int] = {}
    for i, c in enumerate(spec.criterion):
        if isinstance(c, Goals) and not c.goals and c.random <= 0:
            raise SpecError(f"{source}: criterion[{i}]: no goals (give goals = [[x, y, theta], ...] or random = N)")
        if isinstance(c, Goals) and not (c.area[0] < c.area[2] and c.area[1] < c.area[3]):
            raise SpecError(f"{source}: criterion[{i}].area: not [x_min, y_min, x_max, y_max] with min < max")
        if isinstance(c, NoErrors) and c.goals and c.random_goals:
            raise SpecError(f"{source}: criterion[{i}]: goals and random_goals: give one of them")
        if isinstance(c, Parameters):
            _check_params(c, f"{source}: criterion[{i}].params")
        if c.name and c.name in named:
            raise SpecError(f"{source}: criterion[{i}].name: {c.name!r} is criterion[{named[c.name]}]'s name too")
        named.setdefault(c.name, i)
    return spec


def _check_params(c: Parameters, where: str) -> None:
    """Each node's values a table of parameter names (a node's own keys: no empty table)."""
    for node, values in c.params.items():
        if not node:
            raise SpecError(f"{where}: a node's name is empty")
        if not isinstance(values, dict):
            raise SpecError(f"{where}.{node}: not a table of its parameters (give {{ NAME = VALUE }})")
        if not values:
            raise SpecError(f"{where}.{node}: no parameters (give {{ NAME = VALUE }}, or leave the node out)")


_TABLES: dict[str, type[msgspec.Struct]] = {"node": NodeSpec, "topic": TopicSpec, "service": ServiceSpec}


def _hint(what: str, where: str, data: dict[str, object]) -> str:
    """``; did you mean X?`` for an unknown key or check name, from the keys allowed there."""
    table = where.split("[", 1)[0]
    if table == "criterion" and where.endswith((".check", ".at")):
        bad = what.rsplit("'", 2)[-2] if what.count("'") >= 2 else ""
        return suggestion(bad, list(CHECKS) if where.endswith(".check") else ["publisher", "subscriber"])
    if not what.startswith("Object contains unknown field `"):
        return ""
    bad = what.split("`")[1]
    if not where:
        allowed = list(Spec.__struct_fields__)
    elif table == "criterion":
        items = data.get("criterion")
        index = int(where[len("criterion[") :].split("]")[0])
        check = items[index].get("check") if isinstance(items, list) and isinstance(items[index], dict) else None
        allowed = list(CHECKS[check].__struct_fields__) if isinstance(check, str) and check in CHECKS else []
    else:
        allowed = list(_TABLES[table].__struct_fields__) if table in _TABLES else []
    return suggestion(bad, [a for a in allowed if a != "check"])


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
        count = len(criterion.goals) + criterion.random
        return f"{count} goal{'s' * (count != 1)} within {criterion.within_s:g} s and {criterion.distance_m:g} m"
    if isinstance(criterion, Messages):
        return f"{criterion.count} messages on {criterion.key}, every node alive"
    if isinstance(criterion, NoErrors):
        driving = " while driving goals" if criterion.goals or criterion.random_goals else ""
        return f"{criterion.node or 'every node'} runs {criterion.minutes:g} min without errors{driving}"
    if isinstance(criterion, Parameters):
        given = f" and {', '.join(sorted(criterion.params))}'s given values" if criterion.params else ""
        return f"every node runs with its launch file's parameters{given}"
    if isinstance(criterion, RoundTrip):
        return f"message types round-trip on {', '.join(criterion.keys) if criterion.keys else 'every topic'}"
    return f"time_taken within {criterion.within_s:g} s of the client's clock"
