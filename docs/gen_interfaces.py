"""Generate docs/interfaces.md, the interface reference, from the wire contract itself.

    python docs/gen_interfaces.py          # rewrite docs/interfaces.md
    python docs/gen_interfaces.py --check  # exit 1 if docs/interfaces.md is out of date

Field names, types, defaults and the type docstrings come from the msgspec Structs in
``messages/`` (``messages.ALL_TYPES``); keys and token formats from ``messages/keys.py``;
parameters and the world from the nodes' parameter Structs.  What code cannot say (the
unit, range and meaning of each field, who publishes each key and how often) is in
messages/reference.py and messages/key_reference.py (``turtlectl interface show`` reads them too), and
tests/unit/docs/test_gen_interfaces.py fails when a Struct field or a key has no entry
there, when an entry names a field or key that no longer exists, or when
docs/interfaces.md differs from what this script renders: the reference cannot drift.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
for folder in (ROOT, ROOT / "docs"):
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))

import generated  # noqa: E402

from turtlectl.messages import ALL_TYPES, keys  # noqa: E402
from turtlectl.messages.codec import MEDIA_TYPE  # noqa: E402
from turtlectl.messages.codec import type_name as full_name  # noqa: E402
from turtlectl.messages.described import FieldDescription, TypeDescription  # noqa: E402
from turtlectl.messages.fieldtext import default_text, doc, struct_fields, type_name  # noqa: E402
from turtlectl.messages.key_reference import KEYS  # noqa: E402
from turtlectl.messages.params import ParamDescription, ParamInfo  # noqa: E402
from turtlectl.messages.reference import FIELDS  # noqa: E402
from turtlectl.messages.world import Limits, Obstacle, World  # noqa: E402
from turtlectl.nodes.kinds import KINDS  # noqa: E402
from turtlectl.runtime.params import field_comments, param_infos  # noqa: E402
from turtlectl.sim.params import SimParams  # noqa: E402

OUTPUT = ROOT / "docs" / "interfaces.md"
EXAMPLE = ROOT / "docs" / "examples" / "raw_client.py"


def _row(*cells: str) -> str:
    return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"


def types_section() -> list[str]:
    out = ["## Message types", ""]
    out.append(
        "Every type below travels as a msgpack map with a `type` member naming it by its full name, "
        f"`turtlectl/<Type>`, and the sample's encoding is `{MEDIA_TYPE};turtlectl/<Type>` (see *Type names*). "
        "`required` fields must be sent; the others may be left out (their default is used)."
    )
    for cls in ALL_TYPES:
        name = cls.__name__
        out += ["", f"### {name}", "", f"Full name `{full_name(cls)}`.", "", "```text", doc(cls), "```", ""]
        fields = struct_fields(cls)
        if not fields:
            out.append(f'No fields: the map is `{{"type": "{full_name(cls)}"}}` (or empty).')
            continue
        out.append(_row("field", "type", "default", "unit", "range", "meaning"))
        out.append(_row(*["---"] * 6))
        for f in fields:
            unit, span, meaning = FIELDS[name][f.name]
            out.append(_row(f"`{f.name}`", type_name(f.type), default_text(f), unit, span, meaning))
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
        out += ["", f"### kind `{kind}`: {cls.__name__}", "", "```text", doc(cls), "```", ""]
        out += param_table(cls)
    return out + describe_section()


def param_table(cls: type, run_time: bool = True, first: str = "parameter") -> list[str]:
    """A parameter Struct as a table: each parameter (tables' entries dotted) with its type, unit, range,
    default, meaning and (``run_time``) whether it can change at run time (docs/gen_launchfile.py uses it too)."""
    head = [first, "type", "unit", "range", "default", "meaning"] + (["at run time"] if run_time else [])
    out = [_row(*head), _row(*["---"] * len(head))]
    for p in param_infos(cls):
        live = ["yes" if p.run_time else f"no: {p.fixed_because}"] if run_time else []
        out.append(_row(f"`{p.name}`", p.type, p.unit, p.range, p.default, p.meaning, *live))
    return out


def describe_section() -> list[str]:
    """The description every node serves of its parameters, whatever its kind."""
    out = [
        "",
        f"### `{keys.param_describe_key('<node>')}` (JSON): every node's description of its parameters",
        "",
        "Each node, of any kind (a user's own too: it is the runtime's), answers a get on "
        f"`{keys.param_describe_key('<its name>')}` with one JSON object (encoding `application/json`), made from "
        "its parameter Struct: each field's `# unit: meaning` comment, its type's constraints, its default, the "
        "Struct's `FIXED` (what cannot change at run time, and why), and the value it runs with now. "
        "`turtlectl param describe` and `param set` work from this answer alone, so they work on any node. "
        "The tables above are the built-in kinds' answers.",
    ]
    for cls in (ParamDescription, ParamInfo):
        comments = field_comments(cls)
        out += ["", f"#### {cls.__name__}", "", "```text", doc(cls), "```", ""]
        out.append(_row("field", "type", "meaning"))
        out.append(_row(*["---"] * 3))
        for f in struct_fields(cls):
            out.append(_row(f"`{f.name}`", type_name(f.type), comments.get(f.name, "")))
    return out


def descriptions_section() -> list[str]:
    """How a message type is described on the wire, built-in or a user's own (messages.described)."""
    out = [
        f"## Type descriptions: `{keys.type_key('<TypeName>', '<node>')}` (JSON)",
        "",
        "Every node describes each message type it publishes, subscribes to, serves or calls, built-in or its own "
        "(and `turtlectl play` each type of its own it replays, as `play`), "
        f"on `{keys.type_key('<TypeName>', '<node>')}` (encoding `application/json`): a get on "
        f"`{keys.type_key('<TypeName>', '*')}` asks every node that uses the type, `{keys.type_key('*', '*')}` every "
        "type in use (last two chunks of each reply's key: the type's name and the node's). This is how every "
        "turtlectl tool understands a type it was not built with, and how an independent client can too: decode "
        "with the JSON Schema (`schema`), show fields in order with their units (`fields`). A type is described "
        "from its class alone: its wire tag, msgspec's JSON Schema of it (nested Structs in `$defs`), each "
        "field's unit and meaning (a user type's `# unit: meaning` comment after the field; a built-in's from the "
        "tables above) and its docstring's first paragraph. `hash` is `TH01_` and the hex sha256 of the UTF-8 bytes of "
        '`{"name": ..., "schema": ...}` as compact JSON with sorted keys and no escaping beyond JSON\'s own (in Python: '
        '`json.dumps(obj, sort_keys=True, separators=(",", ":"), ensure_ascii=False).encode()`): two nodes that '
        "describe one name with different hashes use two different types under one name, and the tools say so "
        "(`turtlectl list`, `interface list/show`, `echo`, which shows each message by the description it fits).",
        "",
        "Supported field types: bool, int, float, str, bytes (base64 in JSON), enums of str or int values, nested "
        "Structs, lists, tuples, dicts with str keys, and `X | None`; defaults JSON can write.",
    ]
    for cls in (TypeDescription, FieldDescription):
        out += _struct_table(cls, defaults=False)
    return out


def _struct_table(cls: type, defaults: bool) -> list[str]:
    """A Struct's heading, docstring and a row per field (its type, and its default)."""
    out = ["", f"### {cls.__name__}", "", "```text", doc(cls), "```", ""]
    out.append(_row("field", "type", *(["default"] if defaults else [])))
    out.append(_row(*["---"] * (3 if defaults else 2)))
    for f in struct_fields(cls):
        out.append(_row(f"`{f.name}`", type_name(f.type), *([default_text(f)] if defaults else [])))
    return out


def world_section() -> list[str]:
    out = [
        "## World: `turtlectl/world` (JSON)",
        "",
        "The simulator answers a get on `turtlectl/world` with one JSON object (encoding `application/json`), the "
        'launch file\'s `[world]` table: `{"size": 11.088889, "obstacles": [{"x": 2.0, "y": 9.0, "radius": 0.5}, ...]}`.',
    ]
    for cls in (World, Obstacle):
        out += _struct_table(cls, defaults=True)
    limits = ", ".join(f"{f.name} {default_text(f)}" for f in struct_fields(Limits))
    out += [
        "",
        "The robot's limits (launch file `[limits]`; defaults: " + limits + ") are not published: the simulator "
        "enforces them on `turtle1/cmd_vel` and the navigator plans within them.",
    ]
    return out


def _spawn() -> str:
    fields = {f.name: default_text(f) for f in struct_fields(SimParams)}
    return f"x {fields['x']} m, y {fields['y']} m, theta {fields['theta']} rad"


def conventions_section() -> list[str]:
    return [
        "## Conventions",
        "",
        "- **Transport**: Eclipse Zenoh 1.x. `turtlectl launch` runs a router on `tcp/127.0.0.1:7447` (`--port`); "
        "open a session in `client` mode with `connect/endpoints` set to it and multicast scouting off. Nodes are "
        "peers that find each other through the router.",
        f"- **Payloads**: msgpack maps, one per sample, each with a `type` member naming its type by its full name "
        f"(`turtlectl/Pose`: *Type names* below); the sample's encoding says the same: `{MEDIA_TYPE};<package/Type>`. The queryables of parameters, node "
        "details and the world answer JSON instead (`application/json`): `turtlectl/params/<node>`, "
        "`turtlectl/params/<node>/describe`, `turtlectl/nodes/<node>` and `turtlectl/world`.",
        "- **Requests**: the `type` member may be left out; if present it must name the request type. An unknown "
        "field or a missing required one is an error; integers are accepted where floats are expected. Send the "
        f"encoding `{MEDIA_TYPE};<package/Type>` (the services decode by the key's request type whatever it says).",
        "- **JSON**: wherever turtlectl writes a message as JSON (`echo --json` and every `--json`, recordings, the "
        'Foxglove server), a non-finite float is the string `"Infinity"`, `"-Infinity"` or `"NaN"` (JSON has '
        "none, and `null` could not tell an `inf` range from a NaN origin); turtlectl reads them back as floats. "
        "msgpack carries them as floats.",
        "- **Replies**: each reply's encoding names its own type (a `navigate_to` feedback reply is "
        f"`{MEDIA_TYPE};turtlectl/NavigateToFeedback`); the payload's `type` member always does, so dispatch on it. "
        "A request that cannot be used gets a Zenoh *error* reply (`reply.err`) whose payload is an `ErrorReply` "
        f"(encoding `{MEDIA_TYPE};turtlectl/ErrorReply`).",
        "- **Units**: SI (m, s, rad, m/s, rad/s) unless a field says degrees. Headings meant for people "
        "(`TurtleStatus`, the `navigate_to` request, feedback and response) are degrees, reported in [0, 360); "
        "`Pose`, `Twist`, `LaserScan` and `TeleportAbsolute` keep turtlesim's radians. `stamp` is wall-clock ns "
        "since the Unix epoch, `seq` a per-publisher counter from 0.",
        "- **World frame**: origin at the lower-left corner, x to the right, y up, angles counter-clockwise from +x. "
        f"The world is the square [0, size] x [0, size] m (default size {default_text(struct_fields(World)[0])}, turtlesim's). "
        f"The turtle spawns (and `reset` puts it back) at the sim's parameters: default {_spawn()} (the shipped "
        "launch.toml writes them rounded: x 5.544445, y 5.544445; ask `turtlectl/params/sim` for the running values).",
        "- **Domains**: a system started with `turtlectl --domain D launch` runs in the Zenoh namespace `D`: every "
        "key in this document, liveliness tokens included, is `D/<key>` on the router (`D/robot/status`, "
        f"`D/{keys.NODE_TOKEN_PREFIX}/...`). Either open your session with the `namespace` `D` and use the keys as "
        "written here, or use the full keys. Zenoh never matches a chunk that starts with `@` by `*` or `**`, so "
        f"`**` sees no token: find the domains with `{keys.DOMAIN_TOKEN_PREFIX}/*` (declared outside the namespace "
        f"by each supervisor run with `--domain`) or with the selector `{keys.DOMAIN_GRAPHS}`.",
        "- **A fleet's namespaces**: a launch file may run a turtle's navigator, status monitor and obstacle "
        "detector in a namespace named after that turtle (`[[group]]`, how-to *Several turtles*). Their keys are "
        "this document's resolved in it: in namespace `turtle2`, turtle1's keys are turtle2's (`turtle2/pose`, "
        "`turtle2/cmd_vel`) and every other key gets the prefix (`turtle2/navigate_to`, "
        "`turtle2/navigate_to/cancel`, `turtle2/navigate_to/feedback`, `turtle2/robot/status`, "
        "`turtle2/obstacles`); `turtles`, `reset`, `spawn`, `kill`, `turtlectl/...` and the liveliness tokens "
        "stay as written. A namespaced node's name is `turtle2/navigator`, written `turtle2.navigator` where it is "
        f"one key chunk (`{keys.node_key('turtle2/navigator')}`, `{keys.NODE_TOKEN_PREFIX}/turtle2.navigator/...`). "
        "A goal's caller token is the same `@turtlectl/client/<id>` for every navigator.",
    ]


def names_section() -> list[str]:
    """How message types are named (messages.naming): by package, as ROS names them."""
    return [
        "## Type names",
        "",
        "Every message type has a full name `package/Name`, as ROS names a type by its package "
        "(`turtlesim/msg/Pose`), and that full name is its wire tag: the `type` member of every payload and the "
        f"schema in the sample encoding (`{MEDIA_TYPE};turtlectl/Pose`). turtlectl's own types are package "
        '`turtlectl`. A user\'s type declared as `class TurtleStatus(Message, tag="TurtleStatus")` takes its '
        "package from where it is declared: the top-level package or module of its Python module "
        "(`capstone_msgs.py` or `capstone_msgs/...` give `capstone_msgs/TurtleStatus`; a script run as a program "
        'or loaded from a file, its file\'s stem); a tag with a package (`tag="capstone_interfaces/TurtleStatus"`) '
        "is taken as it is. Both parts are identifiers (letters, digits, `_`, not starting with a digit); the "
        "package `turtlectl` is turtlectl's own. So a user's `TurtleStatus` and turtlectl's coexist in one system "
        "and one recording. Where a full name must be one key chunk (the liveliness tokens, type descriptions) "
        f"its slash is written as a dot, as a namespaced node's name is: `capstone_msgs.TurtleStatus` "
        f"(`{keys.type_key('capstone_msgs/TurtleStatus', 'monitor')}`). The tools accept a short name "
        "(`TurtleStatus`) wherever only one known type has it, and refuse an ambiguous one with the full names to "
        "choose from (exit code 2).",
        "",
        "**Recordings made before types were named by package** tag turtlectl's own types bare (`Pose`, "
        "`TurtleStatus`): `info`, `play` and `plot` read those as `turtlectl/Pose`, ..., and `play` sends them under "
        "their full names. A user's type recorded under a bare name keeps that name (it is read and replayed as it "
        "was recorded). A client written for bare names must send and expect full names.",
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
        'canceled (reason "teleported": the simulator calls `turtle1/moving` first, and the navigator ends its goal); '
        "a teleport is not charged to the battery.",
        "- **reset**: served by the sim (pose back to spawn) and the status monitor (its turtle's battery full): one `Ack` from "
        "each, but only with `QueryTarget.ALL` and `ConsolidationMode.NONE` (both replies come on the same key, so "
        'the default consolidation keeps one). A running goal is canceled (reason "reset").',
        "- **Goal services** (any node's, `Node.goal_server`; `navigate_to` is one): on `KEY`, a query carrying "
        "the goal gets feedback replies while it runs, then exactly one result (a refused goal: the result alone). "
        "`KEY/cancel`: `Cancel` -> `Ack` (the cancel's reason passed on to the result). `KEY/feedback`: the same "
        "feedback for observers. The caller's token `@turtlectl/client/<id>` names the goal's caller: `<id>` in "
        "the goal's `client` field when its type has one, else as the query's attachment (UTF-8). One goal at a "
        'time: a newer one ends the running goal ("preempted"). The server also ends a goal "caller gone", '
        '"timeout" (its own limit) and "shut down". In the graph, a goal service has one entity token per type: '
        "`@turtlectl/entity/<node>/<pid>/goal|goal_feedback|goal_result/<Type>/KEY` (`turtlectl action list`).",
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
teleport: {'type': 'turtlectl/Ack', 'ok': True, 'detail': 'teleported to (2, 2, 1.5708 rad)'}
feedback: driving, 3.00 m to go, eta 1.6 s
goal reached in 1.32 s after 13 feedback replies: (5.000, 2.000, 359.8 deg), error 0.0001 m
reset: 2 acks: turtle back at its spawn pose; turtle1: battery full
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
        names_section(),
        services_section(),
        types_section(),
        params_section(),
        descriptions_section(),
        world_section(),
        example_section(SAMPLE_OUTPUT),
    ):
        lines += section + [""]
    return "\n".join(lines).rstrip() + "\n"


def main(argv: list[str]) -> int:
    return generated.main(OUTPUT, render, argv, "gen_interfaces.py")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
