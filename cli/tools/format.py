"""Text for people and for programs: how messages and outcomes are printed (pure)."""

from __future__ import annotations

import csv
import io
import math
import shlex
from typing import TYPE_CHECKING, Any

import msgspec

from turtlectl.messages import Ack, Message, NavigateToFeedback, NavigateToResponse, to_builtins
from turtlectl.messages.angles import degrees_0_360
from turtlectl.messages.codec import type_name
from turtlectl.messages.jsonform import spelled, to_json
from turtlectl.messages.keys import FIRST_TURTLE, resolve
from turtlectl.runtime.client.errors import BadInput

if TYPE_CHECKING:  # launch files (nodes' parameters) are loaded by launch and run only
    from turtlectl.cli.system.launchfile import LaunchPlan

SHORT = 8  # array items shown before "..." unless --full


def _value(value: object, full: bool) -> str:
    if isinstance(value, float):
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        if value == 0:
            return "0"
        text = f"{value:.6g}"
        # 359.99999 is not 360: a heading must read below 360, so give the digits it needs
        return f"{value:.12g}" if float(text) != value and abs(float(text)) >= 360.0 > abs(value) else text
    if isinstance(value, bool):
        return "true" if value else "false"  # as the JSON and the interface reference write it
    if isinstance(value, list):
        items = value if full or len(value) <= SHORT else value[:SHORT]
        more = "" if len(items) == len(value) else f", ... ({len(value)} values)"
        return "[" + ", ".join(_value(v, full) for v in items) + more + "]"
    return str(value)


class Undescribed:
    """A payload no description explains, as decoded (a msgpack or JSON map, or any value):
    shown as a message is, marked undescribed."""

    def __init__(self, data: Any, type_name: str = ""):
        self.data = data
        self.type_name = type_name or (data.get("type", "") if isinstance(data, dict) else "")

    @property
    def name(self) -> str:
        return f"{self.type_name or 'data'} (undescribed)"


Shown = Message | Undescribed


def _name(msg: Shown) -> str:
    return msg.name if isinstance(msg, Undescribed) else type_name(type(msg))


def _fields(msg: Shown) -> dict[str, Any]:
    """The message's fields as plain data, without the type tag."""
    if isinstance(msg, Undescribed):
        data = dict(msg.data) if isinstance(msg.data, dict) else {"value": msg.data}
    else:
        data = to_builtins(msg)
    data.pop("type", None)
    return data


def select_field(msg: Shown, path: str) -> Any:
    """The value at a dotted ``path`` (``ranges.0`` indexes a list); BadInput if there is none."""
    value: Any = _fields(msg)
    for part in path.split("."):
        if isinstance(value, dict) and part in value:
            value = value[part]
        elif isinstance(value, list) and part.lstrip("-").isdigit():
            if not -len(value) <= int(part) < len(value):
                raise BadInput(f"{path!r}: index {part} is out of range ({len(value)} values)")
            value = value[int(part)]
        else:
            raise BadInput(f"{_name(msg)} has no field {path!r}")
    return value


def message_block(msg: Shown, full: bool = False, key: str | None = None) -> str:
    """A readable block, as ``ros2 topic echo`` prints: the type (and the key, when given),
    one ``field: value`` per line, then ``---``."""
    header = f"# {_name(msg)}" + (f" on {key}" if key else "")
    lines = [header] + [f"{name}: {_value(value, full)}" for name, value in _fields(msg).items()]
    return "\n".join(lines) + "\n---"


def value_text(value: Any, full: bool = False) -> str:
    return _value(value, full)


def message_json(msg: Shown, key: str | None = None) -> str:
    """One JSON object on one line (its ``type`` names the message type); with ``key``, a
    ``"key"`` member after ``type`` names the key it came on (echo of a wildcard)."""
    if isinstance(msg, Undescribed):
        where = {"key": key} if key is not None else {}
        return json_value({"type": msg.type_name or None, **where, "undescribed": True, **_fields(msg)})
    if key is None:
        return to_json(msg).decode()
    data = to_builtins(msg)
    return json_value({"type": data.pop("type"), "key": key, **data})


def json_value(value: Any) -> str:
    """``value`` as JSON, infinities and NaN spelled "Infinity", "-Infinity", "NaN" (as recordings
    and the Foxglove server write them: messages.jsonform)."""
    return msgspec.json.encode(spelled(value)).decode()


def csv_header(msg: Shown) -> str:
    return ",".join(_fields(msg))


def _csv_line(values: list[Any]) -> str:
    """One CSV line; arrays and tables (nested Structs) as one quoted JSON cell."""
    out = io.StringIO()
    csv.writer(out, lineterminator="").writerow(
        [json_value(v) if isinstance(v, list | dict | tuple) else v for v in values]
    )
    return out.getvalue()


def csv_row(msg: Shown) -> str:
    """One CSV line of the message's fields; arrays as one quoted JSON cell."""
    return _csv_line(list(_fields(msg).values()))


def fields_header(paths: list[str]) -> str:
    """The CSV header of ``echo --field`` (once or more): the fields' paths as typed."""
    return _csv_line(paths)


def fields_line(values: dict[str, Any], json: bool = False, csv: bool = False, full: bool = False) -> str:
    """The fields ``echo --field`` selected of one message (path -> value), on one line: as
    text separated by spaces, as one CSV line, or in JSON the bare value of one field, an
    object by path of several."""
    if csv:
        return _csv_line(list(values.values()))
    if json:
        return json_value(next(iter(values.values())) if len(values) == 1 else values)
    return " ".join(_value(v, full) for v in values.values())


def heading_text(degrees: float, decimals: int = 1) -> str:
    """A heading (degrees, any value) as people read it: in [0, 360) as printed, so 359.97
    shows as 0.0, never 360.0 (reduced with messages.angles before and after rounding)."""
    shown = degrees_0_360(round(degrees_0_360(degrees), decimals)) + 0.0  # + 0.0: no "-0.0"
    return f"{shown:.{decimals}f}"


def outcome_line(response: NavigateToResponse) -> str:
    """One line for people: what happened to a goal."""
    where = f"at ({response.x:.3f}, {response.y:.3f}, {heading_text(response.theta)} deg)"
    errors = f"error {response.position_error:.4f} m, {response.heading_error:.2f} deg"
    if response.success:
        return f"reached {where} in {response.time_taken:.3f} s ({errors})"
    why = f" ({response.detail})" if response.detail else ""
    if response.refused:
        return f"refused: {response.reason}{why}"
    return f"not reached: {response.reason} after {response.time_taken:.3f} s{why}; {where}, {errors}"


def progress_line(fb: NavigateToFeedback, width: int = 80) -> str:
    """The live progress of a goal on one line of at most ``width - 1`` characters (it is
    rewritten in place, so it must never wrap; the last column stays free because some
    terminals wrap on writing it).  Parts are dropped, least useful first, to fit: the
    elapsed time, the pose, the eta, then the heading; a very narrow line is cut."""
    parts = [  # (priority: lower is kept longer, text)
        (0, f"{fb.state:8s} {fb.distance_remaining:6.3f} m"),
        (3, f"{fb.heading_remaining:5.1f} deg to go"),
        (1, "no scan: avoiding declared obstacles only" if fb.scan_stale else ""),
        (2, f"eta {fb.eta:4.1f} s"),
        (4, f"at ({fb.x:.2f}, {fb.y:.2f}, {heading_text(fb.theta, 0)} deg)"),
        (5, f"{fb.elapsed:.1f} s"),
    ]
    parts = [(rank, text) for rank, text in parts if text]
    room = max(1, width - 1)
    while True:
        line = " | ".join(text for _, text in parts)
        if len(line) <= room or len(parts) == 1:
            return line[:room]
        parts.remove(max(parts, key=lambda p: p[0]))


def ack_lines(acks: list[Ack]) -> str:
    return "\n".join(a.detail for a in acks)


def reset_lines(acks: list[Ack]) -> str:
    """What ``reset`` says: each server's answer on a line (the simulator's, each status
    monitor's naming its turtle), sorted, so that a fleet's come in the same order every time."""
    return "\n".join(sorted(a.detail for a in acks))


def teleport_line(x: float, y: float, theta_degrees: float) -> str:
    """What ``teleport`` says, in the units it was given (m, m, degrees in [0, 360))."""
    return f"teleported to ({x:g}, {y:g}, {heading_text(theta_degrees, 6).rstrip('0').rstrip('.')} deg)"


def plan_text(plan: LaunchPlan) -> str:
    """What ``launch --check`` prints: the validated plan, nodes with their parameters."""
    launch = plan.launch
    w, lim, sup = launch.world, launch.limits, launch.supervisor
    lines = [
        f"{plan.source}: valid",
        f"world: {w.size:g} m square, {len(w.obstacles)} obstacle{'' if len(w.obstacles) == 1 else 's'}"
        + "".join(f"; ({o.x:g}, {o.y:g}) r {o.radius:g}" for o in w.obstacles),
        f"limits: {lim.max_linear_speed:g} m/s, {lim.max_linear_accel:g} m/s^2, "
        f"{lim.max_angular_speed:g} rad/s, {lim.max_angular_accel:g} rad/s^2",
        f"shutdown: SIGINT, {sup.sigint_timeout:g} s, SIGTERM, {sup.sigterm_timeout:g} s, SIGKILL",
    ]
    if plan.args:
        lines.append("arguments:")
    for a in plan.args:
        default = "no default" if a.default is None else f"default {json_value(a.default)}"
        about = f": {a.description}" if a.description else ""
        given = "default" if a.given == "default" else f"{a.given}; {default}"
        lines.append(f"  {a.file}: {a.name} = {json_value(a.value)} ({given}){about}")
    lines.append("nodes:")
    for e in launch.node:
        how = ["required" if e.required else "optional"]
        if e.respawn:
            limit = "no limit" if e.respawn_max == 0 else f"at most {e.respawn_max} in a row"
            if e.start_tries:  # a start that fails before it is ready counts against its own limit
                limit += f"; {e.start_tries} failed starts in a row and no more"
            how.append(f"respawn after {e.respawn_delay:g} s doubling to {e.respawn_delay_max:g} s, {limit}")
        if e.run == "sim" and plan.params[e.name].get("real_time_factor", 1.0) != 1.0:
            how.append(f"makes the clock, {plan.params[e.name]['real_time_factor']:g}x real time")
        elif e.use_sim_time and e.run != "sim":  # the simulator makes the time: it never follows a clock
            how.append("use_sim_time")
        if e.remap:
            keys = (f"{resolve(k, e.namespace)} -> {resolve(k, e.namespace, e.remap)}" for k in e.remap)
            how.append(f"remap {', '.join(keys)}")
        if e.cmd:
            lines.append(f"  {e.name} (cmd {shlex.join(e.cmd)}; {'; '.join(how)})")
        else:
            lines.append(f"  {e.name} (run {e.run}; {'; '.join(how)}): {json_value(plan.params[e.name])}")
    return "\n".join(lines + [f"note: {note}" for note in plan_notes(plan)])


def plan_notes(plan: LaunchPlan) -> list[str]:
    """What is valid in a launch file but likely not meant, or worth knowing at launch: a
    namespace whose turtle the simulator does not make at start (its nodes wait for a pose until
    one is spawned); simulated time at another pace than the wall clock's, and which nodes keep
    the wall clock then; nodes on simulated time in a launch without a simulator (their clock
    comes from elsewhere: a replay's)."""
    sim = next((e for e in plan.launch.node if e.run == "sim"), None)
    if sim is None:
        timed = [e.name for e in plan.launch.node if e.use_sim_time]
        if not timed:
            return []
        return [
            f"simulated time without a simulator: {', '.join(timed)} follow{'s' * (len(timed) == 1)} the clock key, "
            "and wait for it (a replay's: turtlectl play FILE --clock)"
        ]
    made = {FIRST_TURTLE, *(t["name"] for t in plan.params[sim.name].get("turtles", []))}
    return _time_notes(plan, sim.name) + [
        f"no turtle {namespace} at start for the nodes of namespace {namespace}: add it to {sim.name}'s "
        f"params.turtles, or spawn it (turtlectl spawn X Y THETA --name {namespace})"
        for namespace in sorted({e.namespace for e in plan.launch.node if e.namespace} - made)
    ]


def _time_notes(plan: LaunchPlan, sim: str) -> list[str]:
    factor = plan.params[sim].get("real_time_factor", 1.0)
    if factor == 1.0:
        return []
    nodes = [e for e in plan.launch.node if e.run != "sim" and not e.cmd]
    wall = [e.name for e in nodes if not e.use_sim_time]
    note = f"simulated time: {sim} runs {factor:g}x as fast as the wall clock"
    if not wall:
        return [f"{note}; every node follows its clock (use_sim_time)"]
    return [f"{note}; {', '.join(wall)} keep{'s' * (len(wall) == 1)} the wall clock (no use_sim_time)"]


def size_text(size: int) -> str:
    """A byte count for people: B, KiB, MiB or GiB."""
    value = float(size)
    for unit in ("B", "KiB", "MiB"):
        if value < 1024:
            return f"{value:.0f} {unit}" if unit == "B" else f"{value:.1f} {unit}"
        value /= 1024
    return f"{value:.2f} GiB"


def _local_time(ns: int) -> str:
    import datetime

    when = datetime.datetime.fromtimestamp(ns / 1e9).astimezone()
    return f"{when:%Y-%m-%d %H:%M:%S}.{when.microsecond // 1000:03d} {when:%Z}"


def recording_line(elapsed: float, messages: int, size: int) -> str:
    """The live line of `record`: elapsed time, messages written, file size."""
    return f"recording: {elapsed:7.1f} s, {messages} messages, {size_text(size)}"


def info_text(info: Any) -> str:
    """`turtlectl info`, as `ros2 bag info` prints a bag (``info``: cli.recording.reading.Info)."""
    from turtlectl.cli.recording.recover import hint

    lines = [
        f"File:      {info.path}",
        f"Size:      {size_text(info.size)}",
        f"Closed:    {'yes' if info.closed else 'NO: the recorder did not finish it (killed?); what is complete was read'}",
        *([] if info.closed else [f"           {hint(info.path)}"]),
    ]
    if info.count:
        lines += [
            f"Duration:  {info.duration:.3f} s",
            f"Start:     {_local_time(info.start)}",
            f"End:       {_local_time(info.end)}",
        ]
    lines.append(f"Messages:  {info.count}")
    if info.topics:
        rows = [("topic", "type", "count", "rate", "encoding")]
        rows += [(t.key, t.type_name or "(raw)", str(t.count), f"{t.rate:.2f} Hz", t.encoding) for t in info.topics]
        widths = [max(len(r[i]) for r in rows) for i in range(5)]
        lines.append("Topics:")
        for r in rows:
            lines.append(
                "  "
                + "  ".join(
                    c.rjust(w) if i in (2, 3) else c.ljust(w) for i, (c, w) in enumerate(zip(r, widths, strict=True))
                ).rstrip()
            )
    for gap in info.gaps:
        until = _local_time(gap.back) if gap.back else "the end (never back)"
        lines.append(
            f"Gap:       router lost {_local_time(gap.lost)} until {until}: {gap.duration:.1f} s, nothing recorded"
        )
    return "\n".join(lines)


def info_json(info: Any) -> str:
    """`turtlectl info --json`: one object (times in ns since the epoch, duration in s)."""
    import dataclasses

    data = dataclasses.asdict(info)
    data["duration"] = info.duration
    return msgspec.json.encode(data).decode()
