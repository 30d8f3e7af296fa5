"""What a browser and ``turtlectl web`` say to each other over the page's WebSocket (``/ws``): JSON
text frames, one object each, its kind in ``t`` (pure: no zenoh, no I/O).

From the browser (``parse``: anything else is refused with one ``error`` frame, and the
connection stays open):

* ``goal``      ``{turtle, x, y, theta, id}``: a navigate_to goal (m, m, degrees);
* ``cancel``    ``{turtle, id}``: cancel the turtle's running goal;
* ``teleport``  ``{turtle, x, y, theta, id}``: move it there (m, m, degrees);
* ``spawn``     ``{x, y, theta, name?, id}``: a new turtle (a name the simulator picks when empty);
* ``kill``      ``{turtle, id}``;
* ``drive``     ``{turtle, linear, angular}``: m/s and rad/s, sent again every ``DRIVE_REPEAT`` s while a
  key or the pad is held; the server publishes the turtle's cmd_vel and stops the turtle itself
  when ``DRIVE_DEADMAN`` s pass without one (a page that froze or lost its connection);
* ``stop``      ``{turtle}``: a zero Twist now (a key released, the page hidden or blurred);
* ``watch``     ``{keys}``: the topics whose messages the page wants (its echo and its plot);
* ``params``    ``{node, id}``: the node's parameters and their descriptions;
* ``set_param`` ``{node, name, value, id}``: ``value`` as ``turtlectl param set`` reads it (text).

A request with an ``id`` is answered by one ``reply`` ``{id, ok, text, data?}``: ``text`` is what
the command line would print (its error line when ``ok`` is false).

From the server (``hello`` first, then as things change):

* ``hello``   ``{role, secure, can: {drive, command, edit}, world, limits, server}``: what this
  page may do (its login's role on a ``--secure`` system; everything otherwise), the world (m);
* ``world``   ``{world}`` when the simulator's world changes;
* ``frame``   ``{poses, scans, goals, status, sent}``: the newest of each since the last frame
  (never a backlog: a browser that draws slower gets fewer frames); ``sent`` is the server's
  clock (ms since the epoch) as it sends;
* ``outcome`` ``{turtle, success, reason, time_taken, position_error, heading_error, detail}``;
* ``graph``   ``{nodes, clients, topics, goals}`` once a second; a topic's ``rate`` in Hz; ``goals``: the
  goal services served (``navigate_to``, ``turtle2/navigate_to``);
* ``echo``    ``{key, type, message}``: each message on a watched topic (at most ``ECHO_RATE`` a
  second each);
* ``log``     ``{records}``: log records, oldest first;
* ``router``  ``{state: "lost"|"back", connect}``: the system's router went away or came back;
* ``error``   ``{text}``: a frame the server could not take.
"""

from __future__ import annotations

import math
from typing import Any

import msgspec

PATH = "/ws"
DRIVE_REPEAT = 0.1  # s: how often the page repeats a held drive command
DRIVE_DEADMAN = 0.5  # s without a drive command after which the server stops the turtle
ECHO_RATE = 20.0  # Hz: the most messages of one watched topic sent to a page each second
WATCH_LIMIT = 16  # topics one page may watch at once
MAX_FRAME = 64 * 1024  # bytes: the largest frame a page may send


class _In(msgspec.Struct, tag_field="t", forbid_unknown_fields=True, kw_only=True):
    pass


class Asked(_In, kw_only=True):
    id: int = 0  # the reply's id (0: no reply wanted)


class _Placed(Asked, kw_only=True):
    x: float  # m
    y: float  # m
    theta: float  # degrees


class Goal(_Placed, tag="goal", kw_only=True):
    turtle: str


class CancelGoal(Asked, tag="cancel", kw_only=True):
    turtle: str


class Teleport(_Placed, tag="teleport", kw_only=True):
    turtle: str


class Spawn(_Placed, tag="spawn", kw_only=True):
    name: str = ""


class Kill(Asked, tag="kill", kw_only=True):
    turtle: str


class Drive(_In, tag="drive", kw_only=True):
    turtle: str
    linear: float  # m/s
    angular: float  # rad/s


class Stop(_In, tag="stop", kw_only=True):
    turtle: str


class Watch(_In, tag="watch", kw_only=True):
    keys: list[str]


class Params(Asked, tag="params", kw_only=True):
    node: str


class SetParam(Asked, tag="set_param", kw_only=True):
    node: str
    name: str
    value: str


Inbound = Goal | CancelGoal | Teleport | Spawn | Kill | Drive | Stop | Watch | Params | SetParam
KINDS = ("goal", "cancel", "teleport", "spawn", "kill", "drive", "stop", "watch", "params", "set_param")
_decoder = msgspec.json.Decoder(Inbound)


class BadFrame(ValueError):
    """A frame from a page that is not one of ``Inbound``: str() says why, in one line."""


def parse(data: str | bytes) -> Inbound:
    """The browser's frame ``data`` as its Struct; BadFrame naming what is wrong (too large, not
    JSON, an unknown ``t``, a missing or mistyped field, a number that is not finite)."""
    if len(data) > MAX_FRAME:
        raise BadFrame(f"a frame of {len(data)} bytes (at most {MAX_FRAME})")
    try:
        frame = _decoder.decode(data)
    except msgspec.ValidationError as exc:
        text = str(exc)
        if "Invalid value" in text and "$.t" in text or "missing required field `t`" in text:
            raise BadFrame(f"unknown frame kind ({text}); kinds: {', '.join(KINDS)}") from None
        raise BadFrame(text) from None
    except msgspec.DecodeError as exc:
        raise BadFrame(f"not JSON: {exc}") from None
    for name in ("x", "y", "theta", "linear", "angular"):
        value = getattr(frame, name, 0.0)
        if not math.isfinite(value):
            raise BadFrame(f"{name} must be a finite number (got {value})")
    if isinstance(frame, Watch) and len(frame.keys) > WATCH_LIMIT:
        raise BadFrame(f"watch names {len(frame.keys)} topics (at most {WATCH_LIMIT})")
    return frame


class Can(msgspec.Struct, frozen=True):
    """What a page may do: ``drive`` (publish cmd_vel: the keys and the pad), ``command`` (goals,
    cancel, teleport, spawn, kill), ``edit`` (parameters)."""

    drive: bool
    command: bool
    edit: bool


def can(role: str, secure: bool) -> Can:
    """What a page of ``turtlectl web`` logged in as ``role`` may do: everything on a system
    without ``--secure``; on a secure one, what the role's rights allow (runtime.roles)."""
    if not secure:
        return Can(True, True, True)
    from turtlectl.runtime.roles import GOAL_SENDERS, ROLES

    rights = ROLES[role]
    return Can(drive=bool(rights.get("publish")), command=role in GOAL_SENDERS, edit=role in GOAL_SENDERS)


def refusal(role: str, frame: Inbound, allowed: Can) -> str:
    """Why a page logged in as ``role`` may not do ``frame`` ("" if it may): the role's name and
    the role that may."""
    if isinstance(frame, Drive | Stop) and not allowed.drive:
        return f'the {role} role cannot drive (it may not publish cmd_vel): run turtlectl web --role teleop (a launch file: the web node\'s role = "teleop")'
    if isinstance(frame, Goal | CancelGoal | Teleport | Spawn | Kill) and not allowed.command:
        return f"the {role} role cannot send goals, teleport, spawn or kill: run turtlectl web --role operator (a launch file: the web node's role)"
    if isinstance(frame, SetParam) and not allowed.edit:
        return f"the {role} role cannot change parameters: run turtlectl web --role operator (a launch file: the web node's role)"
    return ""


def encode(kind: str, **fields: Any) -> bytes:
    """A server frame: ``{"t": kind, **fields}`` as JSON (an infinite range is null)."""
    return msgspec.json.encode({"t": kind, **fields})


def reply(frame: Asked, ok: bool, text: str, data: Any = None) -> bytes:
    """The answer to ``frame``."""
    return encode("reply", id=frame.id, ok=ok, text=text, data=data)
