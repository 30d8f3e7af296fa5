"""Generate docs/interfaces.md, the interface reference, from the wire contract itself.

    python docs/gen_interfaces.py          # rewrite docs/interfaces.md
    python docs/gen_interfaces.py --check  # exit 1 if docs/interfaces.md is out of date

Field names, types, defaults and the type docstrings come from the msgspec Structs in
``messages/`` (``messages.ALL_TYPES``); keys and token formats from ``messages/keys.py``;
parameters and the world from the nodes' parameter Structs.  What code cannot say (the
unit, range and meaning of each field, who publishes each key and how often) is in the
tables below, and tests/unit/docs/test_gen_interfaces.py fails when a Struct field or a key has no
entry here, when an entry names a field or key that no longer exists, or when
docs/interfaces.md differs from what this script renders: the reference cannot drift.
"""

from __future__ import annotations

import inspect
import math
import sys
from pathlib import Path

import msgspec

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from messages import ALL_TYPES, GoalState, keys  # noqa: E402
from messages.codec import MEDIA_TYPE  # noqa: E402
from messages.world import Limits, Obstacle, World  # noqa: E402
from nodes.kinds import KINDS  # noqa: E402
from sim.params import SimParams  # noqa: E402

OUTPUT = ROOT / "docs" / "interfaces.md"
EXAMPLE = ROOT / "docs" / "examples" / "raw_client.py"

STAMP = ("ns", ">= 0", "wall-clock time at publishing, ns since the Unix epoch (0 if the sender did not stamp it)")
SEQ = ("count", ">= 0", "per-publisher counter from 0; starts again at 0 when the publisher restarts")

# (type, field) -> (unit, range or values, meaning).  Every field of every wire type.
FIELDS: dict[str, dict[str, tuple[str, str, str]]] = {
    "Twist": {
        "linear": (
            "m/s",
            "any finite value; the sim clamps it to [-max_linear_speed, max_linear_speed] and ramps at max_linear_accel; non-finite stops the turtle",
            "speed along the heading; negative drives backwards",
        ),
        "angular": (
            "rad/s",
            "any finite value; the sim clamps it to [-max_angular_speed, max_angular_speed] and ramps at max_angular_accel",
            "yaw rate, counter-clockwise positive",
        ),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "Pose": {
        "x": ("m", "[0, world size]", "position in the world frame"),
        "y": ("m", "[0, world size]", "position in the world frame"),
        "theta": ("rad", "[-pi, pi)", "heading; 0 along +x, counter-clockwise positive"),
        "linear_velocity": ("m/s", "[-max_linear_speed, max_linear_speed]", "speed along the heading"),
        "angular_velocity": ("rad/s", "[-max_angular_speed, max_angular_speed]", "yaw rate"),
        "contact": ("-", "true / false", "the turtle touches a declared obstacle (it stops there, as at a wall)"),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "TurtleStatus": {
        "x": ("m", "[0, world size]", "position"),
        "y": ("m", "[0, world size]", "position"),
        "theta": ("degrees", "[0, 360)", "heading; 0 along +x, counter-clockwise positive"),
        "vel_x": ("m/s", "any", "velocity along the world's x axis"),
        "vel_y": ("m/s", "any", "velocity along the world's y axis"),
        "battery": ("%", "[0, 100]", "simulated charge; drains with time and distance, full after a reset"),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "LaserScan": {
        "angle_min": (
            "rad",
            "[-pi, pi]",
            "angle of beam 0, relative to the heading at origin_theta (0 = straight ahead, CCW positive)",
        ),
        "angle_max": ("rad", "angle_min + at most 2 pi", "angle of the last beam, relative to the heading"),
        "angle_increment": (
            "rad",
            ">= 0",
            "between consecutive beams: beam i points at angle_min + i * angle_increment",
        ),
        "range_min": ("m", ">= 0", "shortest range the sensor reports"),
        "range_max": ("m", "> range_min", "longest range; farther hits are not reported"),
        "ranges": (
            "m",
            "[0, range_max] or inf",
            'one per beam: distance to the first hit, walls and declared obstacles (and phantoms) alike; inf = nothing within range_max (null in `echo --json`, "Infinity" in recordings); 0 on every beam inside an obstacle',
        ),
        "origin_x": ("m", "[0, world size] or NaN", "where the scan was taken (the turtle's position); NaN if unknown"),
        "origin_y": ("m", "[0, world size] or NaN", "where the scan was taken; NaN if unknown"),
        "origin_theta": (
            "rad",
            "[-pi, pi) or NaN",
            "the turtle's heading when the scan was taken; world angle of beam i = origin_theta + angle_min + i * angle_increment",
        ),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "NavigateToRequest": {
        "x": (
            "m",
            "[0, world size], at least the navigator's robot_radius + clearance from every declared obstacle",
            "goal position",
        ),
        "y": (
            "m",
            "[0, world size], at least the navigator's robot_radius + clearance from every declared obstacle",
            "goal position",
        ),
        "theta": ("degrees", "any finite value (taken modulo 360)", "goal heading"),
        "client": (
            "-",
            "one key chunk, or empty",
            'id of the caller\'s liveliness token @turtlectl/client/<id>; when that token vanishes the goal is canceled ("caller gone"); empty: none',
        ),
    },
    "NavigateToFeedback": {
        "state": ("-", ", ".join(f'"{s.value}"' for s in GoalState), "what the turtle does now"),
        "distance_remaining": ("m", ">= 0", "distance to the goal position along the path"),
        "heading_remaining": (
            "degrees",
            "[0, 180]",
            "absolute difference between the heading now and the goal heading",
        ),
        "eta": ("s", ">= 0", "estimated time to arrival within the robot's limits"),
        "elapsed": ("s", ">= 0", "since the navigator received the goal"),
        "x": ("m", "[0, world size]", "position now"),
        "y": ("m", "[0, world size]", "position now"),
        "theta": ("degrees", "[0, 360)", "heading now"),
        "goal_x": ("m", "[0, world size]", "the goal being run"),
        "goal_y": ("m", "[0, world size]", "the goal being run"),
        "goal_theta": ("degrees", "[0, 360)", "the goal heading"),
        "scan_stale": (
            "-",
            "true / false",
            "no scan newer than the navigator's scan_timeout: it avoids only the declared obstacles",
        ),
        "path": (
            "m",
            "points (x, y) in the world",
            "the way the turtle follows, from where it was planned to the goal: a straight way is its two ends, "
            'arcs round obstacles a point every 10 degrees; empty while there is no way (state "replanning")',
        ),
        "replans": (
            "-",
            ">= 0",
            "times the path was planned again during this goal (something the scan sees in the way, or the turtle off its path)",
        ),
        "stamp": STAMP,
        "seq": SEQ,
    },
    "NavigateToResponse": {
        "success": ("-", "true / false", "the goal was reached within position_tolerance and heading_tolerance"),
        "time_taken": ("s", ">= 0", "from the navigator receiving the request to this reply"),
        "reason": (
            "-",
            "text",
            'empty on success; else a short word for programs: "invalid goal", "unreachable" (no way round the declared obstacles; detail says why), "battery low", "preempted", "canceled", "caller gone", "teleported", "reset", "blocked", "no pose", "timeout", "navigator shut down"',
        ),
        "refused": (
            "-",
            "true / false",
            "the goal never started (invalid, unreachable, battery low); x, y, theta are where the turtle is",
        ),
        "position_error": ("m", ">= 0", "final distance to the goal position"),
        "heading_error": ("degrees", "[0, 180]", "final absolute heading error"),
        "x": ("m", "[0, world size]", "final position"),
        "y": ("m", "[0, world size]", "final position"),
        "theta": ("degrees", "[0, 360)", "final heading"),
        "detail": (
            "-",
            "text, or empty",
            "a sentence for people: why, and what to do next (e.g. the battery level and `turtlectl reset`, what blocked the way); not meant to be parsed",
        ),
    },
    "Cancel": {
        "reason": ("-", "text, or empty", 'what the canceled goal\'s caller is told (empty: "canceled")'),
    },
    "TeleportAbsolute": {
        "x": ("m", "[0, world size], not inside a declared obstacle", "new position"),
        "y": ("m", "[0, world size], not inside a declared obstacle", "new position"),
        "theta": (
            "rad",
            "any finite value (wrapped to [-pi, pi))",
            "new heading, radians as turtlesim's (turtlectl teleport takes degrees)",
        ),
    },
    "Reset": {},
    "Ack": {
        "ok": ("-", "true / false", "the request was carried out (false: e.g. cancel with no goal running)"),
        "detail": ("-", "text", "a sentence for people saying what was done; not meant to be parsed"),
    },
    "ErrorReply": {
        "error": (
            "-",
            "text",
            "why the request could not be used (undecodable, unknown field, missing field, impossible pose)",
        ),
    },
}

# key -> (kind, payload, from -> to, when, how to use it)
KEYS: dict[str, tuple[str, str, str, str, str]] = {
    keys.CMD_VEL: (
        "topic",
        "Twist",
        "navigator -> sim",
        "with each pose, only while a goal runs",
        "subscribe; publish to drive by hand (the sim stops 1 s (cmd_timeout) after the last one)",
    ),
    keys.POSE: ("topic", "Pose", "sim -> anyone", "62.5 Hz (every 16 ms simulation step)", "subscribe"),
    keys.STATUS: ("topic", "TurtleStatus", "status_monitor -> anyone", "10 Hz", "subscribe"),
    keys.OBSTACLES: ("topic", "LaserScan", "obstacle_detector -> navigator, anyone", "5 Hz", "subscribe"),
    keys.FEEDBACK: (
        "topic",
        "NavigateToFeedback",
        "navigator -> anyone (observers)",
        "10 Hz, only while a goal runs",
        "subscribe",
    ),
    keys.NAVIGATE_TO: (
        "service",
        "NavigateToRequest -> NavigateToFeedback replies, then one NavigateToResponse",
        "client -> navigator",
        "per goal; feedback at feedback_rate (10 Hz)",
        "get with ConsolidationMode.NONE (the default consolidation delivers only the response, at the end)",
    ),
    keys.CANCEL: (
        "service",
        "Cancel -> Ack",
        "client -> navigator",
        "on request",
        "get; Ack ok=false when no goal is running",
    ),
    keys.TELEPORT: (
        "service",
        "TeleportAbsolute -> Ack",
        "client -> sim",
        "on request",
        "get; an ErrorReply (reply.err) for an impossible pose",
    ),
    keys.RESET: (
        "service",
        "Reset -> Ack from each server",
        "client -> sim (pose), status_monitor (battery)",
        "on request",
        "get with QueryTarget.ALL and ConsolidationMode.NONE for both Acks (the default consolidation returns one)",
    ),
    keys.WORLD_KEY: (
        "queryable",
        "JSON (application/json): World",
        "sim -> anyone (turtlectl view)",
        "on request",
        "get; fixed for the sim's lifetime",
    ),
    keys.params_key("<node>"): (
        "queryable",
        "JSON (application/json): the node's parameters",
        "each node -> anyone",
        "on request",
        "get; the parameters the node runs with",
    ),
    f"{keys.NODE_TOKEN_PREFIX}/<name>/<pid>/<host>/<start_ns>": (
        "liveliness token",
        "-",
        "each node -> anyone",
        "while the node runs",
        f"liveliness get or subscribe on `{keys.NODE_TOKEN_PREFIX}/**`",
    ),
    f"{keys.ENTITY_TOKEN_PREFIX}/<node>/<pid>/<role>/<Type>/<key>": (
        "liveliness token",
        "-",
        "each node -> anyone (turtlectl list)",
        "while the entity exists",
        f"liveliness get on `{keys.ENTITY_TOKEN_PREFIX}/**`; role is pub, sub or srv; Type the message type (a service's request type; JSON for the JSON queryables); key may contain /",
    ),
    f"{keys.CLIENT_TOKEN_PREFIX}/<id>": (
        "liveliness token",
        "-",
        "a navigate_to caller -> navigator",
        "while the caller waits for its goal",
        "declare it before the request, put <id> in NavigateToRequest.client; optional",
    ),
    f"{keys.DOMAIN_TOKEN_PREFIX}/<domain>": (
        "liveliness token",
        "-",
        "a supervisor run with --domain -> anyone",
        "while the supervisor runs",
        "liveliness get on `@turtlectl/domain/*` from a session without namespace",
    ),
}


def _type_name(t: msgspec.inspect.Type) -> str:
    if isinstance(t, msgspec.inspect.FloatType):
        return "float"
    if isinstance(t, msgspec.inspect.IntType):
        return "int"
    if isinstance(t, msgspec.inspect.BoolType):
        return "bool"
    if isinstance(t, msgspec.inspect.StrType):
        return "str"
    if isinstance(t, msgspec.inspect.EnumType) and issubclass(t.cls, str):
        return "str"  # on the wire, the value; the range column lists the values
    if isinstance(t, msgspec.inspect.ListType):
        return f"list[{_type_name(t.item_type)}]"
    if isinstance(t, msgspec.inspect.StructType):
        return t.cls.__name__
    if isinstance(t, msgspec.inspect.DictType):
        return "map"
    return type(t).__name__.removesuffix("Type").lower()


def _default(field: msgspec.inspect.Field) -> str:
    if field.required:
        return "required"
    value = field.default
    if value is msgspec.NODEFAULT and field.default_factory is not msgspec.NODEFAULT:
        value = field.default_factory()
    if isinstance(value, float):
        return "NaN" if math.isnan(value) else f"{value:.8g}"
    if isinstance(value, msgspec.Struct):
        return "(table)"
    return msgspec.json.encode(value).decode()


def _doc(cls: type) -> str:
    return inspect.cleandoc(cls.__doc__ or "").strip()


def _fields(cls: type) -> list[msgspec.inspect.Field]:
    return list(msgspec.inspect.type_info(cls).fields)


def _comments(cls: type) -> dict[str, str]:
    """``# comments`` after the fields in the class's source (Gains keeps its units there)."""
    found: dict[str, str] = {}
    for line in inspect.getsource(cls).splitlines():
        name, colon, rest = line.strip().partition(":")
        if colon and name.isidentifier() and "#" in rest:
            found[name] = rest.split("#", 1)[1].strip()
    return found


def _row(*cells: str) -> str:
    return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"


def types_section() -> list[str]:
    out = ["## Message types", ""]
    out.append(
        "Every type below travels as a msgpack map with a `type` member naming it, and the sample's encoding is "
        f"`{MEDIA_TYPE};<Type>`. `required` fields must be sent; the others may be left out (their default is used)."
    )
    for cls in ALL_TYPES:
        name = cls.__name__
        out += ["", f"### {name}", "", "```text", _doc(cls), "```", ""]
        fields = _fields(cls)
        if not fields:
            out.append(f'No fields: the map is `{{"type": "{name}"}}` (or empty).')
            continue
        out.append(_row("field", "type", "default", "unit", "range", "meaning"))
        out.append(_row(*["---"] * 6))
        for f in fields:
            unit, span, meaning = FIELDS[name][f.name]
            out.append(_row(f"`{f.name}`", _type_name(f.type), _default(f), unit, span, meaning))
    return out


def keys_section() -> list[str]:
    out = ["## Keys", ""]
    out.append(_row("key", "kind", "payload", "from -> to", "when", "how"))
    out.append(_row(*["---"] * 6))
    for key, (kind, payload, who, when, how) in KEYS.items():
        out.append(_row(f"`{key}`", kind, payload, who, when, how))
    return out


def params_section() -> list[str]:
    out = [
        "## Parameters: `turtlectl/params/<node>` (JSON)",
        "",
        "Each node answers a get on `turtlectl/params/<its name>` with one JSON object (encoding `application/json`): "
        "the parameters it runs with, as the launch file's `[node.params]` table after validation, every field "
        "present. Its layout depends on the node's kind (`run` in the launch file):",
    ]
    for kind, spec in KINDS.items():
        cls = spec.params
        out += ["", f"### kind `{kind}`: {cls.__name__}", "", "```text", _doc(cls), "```", ""]
        out.append(_row("field", "type", "default", "note"))
        out.append(_row(*["---"] * 4))
        for f in _fields(cls):
            out.append(
                _row(
                    f"`{f.name}`",
                    _type_name(f.type),
                    _default(f),
                    "table:" if isinstance(f.type, msgspec.inspect.StructType) else "",
                )
            )
            if isinstance(f.type, msgspec.inspect.StructType):
                notes = _comments(f.type.cls)
                for sub in _fields(f.type.cls):
                    out.append(
                        _row(f"`{f.name}.{sub.name}`", _type_name(sub.type), _default(sub), notes.get(sub.name, ""))
                    )
    return out


def world_section() -> list[str]:
    out = [
        "## World: `turtlectl/world` (JSON)",
        "",
        "The simulator answers a get on `turtlectl/world` with one JSON object (encoding `application/json`), the "
        'launch file\'s `[world]` table: `{"size": 11.088889, "obstacles": [{"x": 2.0, "y": 9.0, "radius": 0.5}, ...]}`.',
    ]
    for cls in (World, Obstacle):
        out += ["", f"### {cls.__name__}", "", "```text", _doc(cls), "```", ""]
        out.append(_row("field", "type", "default"))
        out.append(_row(*["---"] * 3))
        for f in _fields(cls):
            out.append(_row(f"`{f.name}`", _type_name(f.type), _default(f)))
    limits = ", ".join(f"{f.name} {_default(f)}" for f in _fields(Limits))
    out += [
        "",
        "The robot's limits (launch file `[limits]`; defaults: " + limits + ") are not published: the simulator "
        "enforces them on `turtle1/cmd_vel` and the navigator plans within them.",
    ]
    return out


def _spawn() -> str:
    fields = {f.name: _default(f) for f in _fields(SimParams)}
    return f"x {fields['x']} m, y {fields['y']} m, theta {fields['theta']} rad"


def conventions_section() -> list[str]:
    return [
        "## Conventions",
        "",
        "- **Transport**: Eclipse Zenoh 1.x. `turtlectl launch` runs a router on `tcp/127.0.0.1:7447` (`--port`); "
        "open a session in `client` mode with `connect/endpoints` set to it and multicast scouting off. Nodes are "
        "peers that find each other through the router.",
        f"- **Payloads**: msgpack maps, one per sample, each with a `type` member naming its type; the sample's "
        f"encoding says the same: `{MEDIA_TYPE};<Type>`. Two queryables answer JSON instead (`application/json`): "
        "`turtlectl/params/<node>` and `turtlectl/world`.",
        "- **Requests**: the `type` member may be left out; if present it must name the request type. An unknown "
        "field or a missing required one is an error; integers are accepted where floats are expected. Send the "
        f"encoding `{MEDIA_TYPE};<Type>` (the services decode by the key's request type whatever it says).",
        "- **Replies**: each reply's encoding names its own type (a `navigate_to` feedback reply is "
        f"`{MEDIA_TYPE};NavigateToFeedback`); the payload's `type` member always does, so dispatch on it. A request "
        "that cannot be used gets a Zenoh *error* reply (`reply.err`) whose payload is an `ErrorReply` (encoding "
        f"`{MEDIA_TYPE};ErrorReply`).",
        "- **Units**: SI (m, s, rad, m/s, rad/s) unless a field says degrees. Headings meant for people "
        "(`TurtleStatus`, the `navigate_to` request, feedback and response) are degrees, reported in [0, 360); "
        "`Pose`, `Twist`, `LaserScan` and `TeleportAbsolute` keep turtlesim's radians. `stamp` is wall-clock ns "
        "since the Unix epoch, `seq` a per-publisher counter from 0.",
        "- **World frame**: origin at the lower-left corner, x to the right, y up, angles counter-clockwise from +x. "
        f"The world is the square [0, size] x [0, size] m (default size {_default(_fields(World)[0])}, turtlesim's). "
        f"The turtle spawns (and `reset` puts it back) at the sim's parameters: default {_spawn()} (the shipped "
        "launch.toml writes them rounded: x 5.544445, y 5.544445; ask `turtlectl/params/sim` for the running values).",
        "- **Domains**: a system started with `turtlectl --domain D launch` runs in the Zenoh namespace `D`: every "
        "key in this document, liveliness tokens included, is `D/<key>` on the router (`D/robot/status`, "
        f"`D/{keys.NODE_TOKEN_PREFIX}/...`). Either open your session with the `namespace` `D` and use the keys as "
        "written here, or use the full keys. Zenoh never matches a chunk that starts with `@` by `*` or `**`, so "
        f"`**` sees no token: find the domains with `{keys.DOMAIN_TOKEN_PREFIX}/*` (declared outside the namespace "
        f"by each supervisor run with `--domain`) or with the selector `{keys.DOMAIN_GRAPHS}`.",
    ]


def services_section() -> list[str]:
    return [
        "## Calling the services",
        "",
        "- **navigate_to**: one goal at a time. Send a `NavigateToRequest` with `ConsolidationMode.NONE`: about 10 "
        "times a second a `NavigateToFeedback` reply, then exactly one `NavigateToResponse`, after which the query "
        "ends. A refused goal (`refused` true: invalid, unreachable, battery low) gets only the response. A new goal preempts "
        'the running one (its caller gets reason "preempted"). Without `NONE` Zenoh consolidates the replies and '
        "you get the response alone, at the end. Give the query a `timeout` longer than the goal can take "
        "(the navigator's `goal_timeout`, 30 s by default; Zenoh's own default is 10 s): when the query times out "
        "the client gets no response, and the goal keeps running unless you hold the caller's token below. The "
        'pose in a response ended by "teleported" or "reset" is where the turtle was when the goal was '
        "canceled, before it was moved.",
        "- **The caller-gone rule** (optional for a raw client): declare the liveliness token "
        f"`{keys.CLIENT_TOKEN_PREFIX}/<id>` (in the system's domain), put `<id>` in `NavigateToRequest.client`, and "
        "keep the token until the response. When it vanishes (undeclared, the session closed, the process killed) "
        'the navigator cancels the goal with reason "caller gone". turtlectl uses `<pid>-<8 hex digits>`; any '
        "single key chunk works. Without `client` the goal runs to its end whatever happens to the caller.",
        '- **navigate_to/cancel**: `Cancel` -> `Ack`; ok=false ("no goal is running") when there is nothing to '
        'cancel. The running goal\'s caller gets its `NavigateToResponse` with the reason (default "canceled"); '
        "the navigator commands a stop at once.",
        "- **turtle1/teleport_absolute**: `TeleportAbsolute` (radians) -> `Ack` once the new pose has been published; "
        "an `ErrorReply` for a pose outside the world, inside a declared obstacle or not finite. A running goal is "
        'canceled (reason "teleported"); a teleport is not charged to the battery.',
        "- **reset**: served by the sim (pose back to spawn) and the status monitor (battery full): one `Ack` from "
        "each, but only with `QueryTarget.ALL` and `ConsolidationMode.NONE` (both replies come on the same key, so "
        'the default consolidation keeps one). A running goal is canceled (reason "reset").',
        "- **One navigator**: a second navigator refuses to start while one serves `navigate_to` (in the same domain).",
        "- **Liveliness**: `@turtlectl/node/<name>/<pid>/<host>/<start_ns>`, where host is the machine's name with "
        "`/ * $ # ?` and spaces replaced by `_` and start_ns the node's start, wall-clock ns. The selector "
        f"`{keys.NODE_TOKEN_PREFIX}/*` matches no node: use `{keys.NODE_TOKEN_PREFIX}/**`.",
    ]


def example_section(sample_output: str) -> list[str]:
    return [
        "## Worked example: a raw client",
        "",
        "[`docs/examples/raw_client.py`](examples/raw_client.py), written from this document alone (plain "
        "zenoh-python and plain msgpack, no turtlectl import), run against a live system "
        "(`python docs/examples/raw_client.py tcp/127.0.0.1:7447`, or with a domain as the second argument); "
        "tests/integration/test_client_rules.py runs it against the real system:",
        "",
        "```python",
        EXAMPLE.read_text().rstrip(),
        "```",
        "",
        "Output of one run:",
        "",
        "```text",
        sample_output.rstrip(),
        "```",
    ]


SAMPLE_OUTPUT = """\
4 nodes: navigator (pid 9745), obstacle_detector (pid 9749), sim (pid 9743), status_monitor (pid 9747)
status: x 4.26 m, y 1.00 m, heading 0.0 deg, battery 97.1 %
world: 11.089 m square, 3 obstacles
teleport: {'type': 'Ack', 'ok': True, 'detail': 'teleported to (2, 2, 1.5708 rad)'}
feedback: driving, 3.00 m to go, eta 1.6 s
goal reached in 1.32 s after 13 feedback replies: (5.000, 2.000, 359.8 deg), error 0.0001 m
reset: 2 acks: battery full; turtle back at its spawn pose
cancel: ok=False (no goal is running)
"""


def render() -> str:
    lines = [
        "# turtlectl interfaces",
        "",
        "<!-- Generated by docs/gen_interfaces.py from messages/ and the nodes' parameter Structs: do not edit by "
        "hand; run `python docs/gen_interfaces.py` (tests/unit/docs/test_gen_interfaces.py checks it is up to date). -->",
        "",
        "Everything a client needs to talk to a running turtlectl system with plain Zenoh and any msgpack library "
        "(`msgspec`, installed with turtlectl, or `msgpack`): every "
        "key, every message type with each field's unit and range, the JSON queryables, the liveliness tokens, and "
        "a worked example that was run against a live system.",
        "",
    ]
    for section in (
        conventions_section(),
        keys_section(),
        services_section(),
        types_section(),
        params_section(),
        world_section(),
        example_section(SAMPLE_OUTPUT),
    ):
        lines += section + [""]
    return "\n".join(lines).rstrip() + "\n"


def main(argv: list[str]) -> int:
    text = render()
    if "--check" in argv:
        if OUTPUT.read_text() != text:
            print(f"{OUTPUT} is out of date: run python docs/gen_interfaces.py", file=sys.stderr)
            return 1
        return 0
    OUTPUT.write_text(text)
    print(f"wrote {OUTPUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
