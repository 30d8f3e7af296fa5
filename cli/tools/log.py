"""``turtlectl log``: every node's log in one place, as ROS's ``/rosout`` and rqt_console.

Every node publishes each record it logs on ``turtlectl/log/<node>`` and answers a get there
with its last records (runtime.log_stream).  ``read`` asks every running node for those,
prints them merged by time, and with ``follow`` goes on with each record as it comes; the
filters (level, node, since) and the two ways of writing a record (a line for people,
coloured by level on a terminal; a JSON object) are pure functions.  Nothing here prints.
"""

from __future__ import annotations

import dataclasses
import os
import queue
import re
import time
from collections.abc import Iterator, Mapping

import zenoh

from turtlectl.cli.args import level_named
from turtlectl.cli.selection import selects
from turtlectl.cli.tools.routerwatch import watch
from turtlectl.messages import DecodeError, Log, decode, to_json
from turtlectl.messages.keys import LOG_KEYS
from turtlectl.runtime.client.errors import BadInput, Unreachable
from turtlectl.runtime.client.session import client_session, domain_hint, live_graph
from turtlectl.runtime.loader import nearest

#: the levels by name, as Python's logging and ROS number them (ROS's FATAL is CRITICAL)
LEVELS = {"DEBUG": 10, "INFO": 20, "WARNING": 30, "ERROR": 40, "CRITICAL": 50}
_NAMES = {number: name for name, number in LEVELS.items()}
#: s every running node has to answer with its recent records
RECENT_TIMEOUT = 2.0
_DURATION = re.compile(r"(\d+(?:\.\d*)?|\.\d+)(ms|s|m|h|d)?")
_UNITS = {"ms": 0.001, "s": 1.0, "m": 60.0, "h": 3600.0, "d": 86400.0}

# ANSI colours by level (the least severe level each starts at); INFO colours only its name
_COLOURS = ((50, "1;31"), (40, "31"), (30, "33"), (20, "32"), (0, "2"))
_RESET = "\033[0m"


def level_number(text: str) -> int:
    """A level as typed (any case): DEBUG, INFO, WARNING (WARN), ERROR, CRITICAL (FATAL)."""
    return LEVELS[level_named(text, LEVELS, "; WARN and FATAL as ROS spells them")]


def level_name(level: int) -> str:
    """A level's name (``Level 25`` for one between the named ones, as Python's logging says)."""
    return _NAMES.get(level, f"Level {level}")


def since_seconds(text: str) -> float:
    """A duration as typed for --since: ``30s``, ``5m``, ``1h30m``, ``250ms``, ``2d``; a bare
    number is seconds."""
    compact = text.strip().lower().replace(" ", "")
    parts = list(_DURATION.finditer(compact))
    if not compact or "".join(p.group(0) for p in parts) != compact:
        raise BadInput(f"--since {text!r}: give a duration such as 30s, 5m, 1h30m or 250ms (a bare number is seconds)")
    seconds = sum(float(p.group(1)) * _UNITS[p.group(2) or "s"] for p in parts)
    if seconds <= 0:
        raise BadInput(f"--since {text!r}: a duration longer than 0")
    return seconds


def node_matches(name: str, patterns: tuple[str, ...]) -> bool:
    """Whether node ``name`` is one of ``patterns``, node selectors as ``launch --only`` takes
    them (cli.selection: names, globs such as ``turtle2/*``, namespaces, turtles); any node when
    there are none."""
    return not patterns or any(selects(p, name) for p in patterns)


def unmatched(patterns: tuple[str, ...], running: list[str]) -> str:
    """Why ``--node patterns`` shows nothing: none matches a ``running`` node; the running node
    nearest each plain name (not a glob) suggested, as every command that takes a node name does."""
    near = [nearest(p.lstrip("/"), running) for p in patterns if not any(c in p for c in "*?[")]
    named = [n for n in dict.fromkeys(near) if n]
    hint = f"; did you mean {', '.join(named)}?" if named else ""
    return f"no running node matches --node {', '.join(patterns)}{hint} (running: {', '.join(running)})"


@dataclasses.dataclass(frozen=True)
class LogFilter:
    """Which records to show: at ``level`` or above, of a node ``nodes`` matches (none: every
    node), stamped at ``since_ns`` or later (0: whenever)."""

    level: int = 0
    nodes: tuple[str, ...] = ()
    since_ns: int = 0

    def wants(self, record: Log) -> bool:
        return record.level >= self.level and record.stamp >= self.since_ns and node_matches(record.node, self.nodes)


def use_colour(is_terminal: bool, environ: Mapping[str, str] = os.environ) -> bool:
    """Colours on a terminal only, and never with ``NO_COLOR`` set (no-color.org) or a dumb terminal."""
    return is_terminal and not environ.get("NO_COLOR") and environ.get("TERM") != "dumb"


def _colour(level: int) -> str:
    return next(code for least, code in _COLOURS if level >= least)


def clock_time(stamp: int) -> str:
    """``HH:MM:SS.mmm``, local time, of a stamp in ns since the epoch."""
    seconds, ns = divmod(stamp, 1_000_000_000)
    return time.strftime("%H:%M:%S", time.localtime(seconds)) + f".{ns // 1_000_000:03d}"


def text_of(record: Log, colour: bool = False) -> str:
    """A record for people: ``12:04:31.250 INFO     navigator: goal reached``; the lines after
    the first (a traceback) indented.  With ``colour``: DEBUG dim, INFO's name green, WARNING
    yellow, ERROR red, CRITICAL bold red."""
    name = level_name(record.level)
    first, *rest = record.message.rstrip("\n").split("\n")
    rest = [f"    {line}" if line else "" for line in rest]
    if not colour:
        return "\n".join([f"{clock_time(record.stamp)} {name:<8} {record.node}: {first}", *rest])
    code = _colour(record.level)
    if LEVELS["INFO"] <= record.level < LEVELS["WARNING"]:  # INFO: only its name coloured
        head = f"{clock_time(record.stamp)} \033[{code}m{name:<8}{_RESET} {record.node}: {first}"
        return "\n".join([head, *rest])
    lines = [f"{clock_time(record.stamp)} {name:<8} {record.node}: {first}", *rest]
    return "\n".join(f"\033[{code}m{line}{_RESET}" for line in lines)


def json_of(record: Log) -> str:
    """A record as one JSON object on one line, as ``echo --json`` writes a Log: ``type``,
    ``level`` (a number), ``node``, ``message``, ``file``, ``function``, ``line``, ``stamp``, ``seq``."""
    return to_json(record).decode()


class Notice:
    """A line for the reader's stderr between the records (``text``)."""

    def __init__(self, text: str):
        self.text = text


def _decoded(payload: bytes) -> Log | None:
    try:
        return decode(payload, Log)
    except DecodeError:  # not a record (a raw publisher on a log key): nothing to show
        return None


def recent(session: zenoh.Session, timeout: float = RECENT_TIMEOUT) -> list[Log]:
    """Every running node's recent records (each node's last ones, runtime.log_stream.RECENT),
    merged by time."""
    replies = session.get(
        LOG_KEYS, target=zenoh.QueryTarget.ALL, consolidation=zenoh.ConsolidationMode.NONE, timeout=timeout
    )
    records = [r for reply in replies if reply.ok is not None and (r := _decoded(reply.ok.payload.to_bytes()))]
    return sorted(records, key=lambda r: (r.stamp, r.node, r.seq))


def _running(session: zenoh.Session) -> list[str]:
    """The names of the nodes running in this client's domain (not those of other domains)."""
    return [n.name for n in live_graph(session).nodes if not n.domain]


def _nothing(held: int, wanted: LogFilter) -> str:
    """Why a read without --follow printed no record."""
    if held:
        given = [
            o for o, on in (("--level", wanted.level), ("--node", wanted.nodes), ("--since", wanted.since_ns)) if on
        ]
        return f"none of the {held} records the running nodes hold matches {' and '.join(given)}"
    return "the running nodes hold no records (each keeps its last ones at its log level: `turtlectl log-level NODE DEBUG` for more)"


def read(
    connect: str, domain: str, wanted: LogFilter, follow: bool = False, exit_on_loss: bool = False
) -> Iterator[Log | Notice]:
    """The records ``wanted`` of every running node: first their recent ones, oldest first;
    with ``follow``, then each new one as it comes, until the caller stops (Ctrl-C).

    Without ``follow``, Unreachable when no node runs, or none matches ``wanted.nodes``; with
    it, a Notice says so and it waits for them.  A lost router and its return are a Notice each
    (cli.tools.routerwatch); with ``exit_on_loss``, RouterLost (Unreachable) instead."""
    with client_session(connect, domain) as session:
        inbox: queue.SimpleQueue[bytes] = queue.SimpleQueue()
        live = session.declare_subscriber(LOG_KEYS, lambda s: inbox.put(s.payload.to_bytes())) if follow else None
        try:
            running = _running(session)
            problem = ""
            if not running:
                problem = "no turtlectl node runs here"
                if not follow:
                    raise Unreachable(
                        f"{problem}: no log to read (is `turtlectl launch` running?){domain_hint(connect, domain)}"
                    )
            elif not any(node_matches(name, wanted.nodes) for name in running):
                problem = unmatched(wanted.nodes, running)
                if not follow:
                    raise Unreachable(problem)
            if problem:
                yield Notice(f"{problem}; waiting for its records (Ctrl-C stops)")
            shown: set[tuple[str, int, int]] = set()  # the recent records: not again when they also come live
            held = recent(session)
            matching = [r for r in held if wanted.wants(r)]
            for record in held:
                shown.add((record.node, record.stamp, record.seq))
            yield from matching
            if live is None:
                if not matching and not problem:
                    yield Notice(_nothing(len(held), wanted))
                return
            router = watch(session, connect, "log records", exit_on_loss)
            while True:
                try:
                    payload = inbox.get(timeout=0.1)  # short waits keep Ctrl-C responsive
                except queue.Empty:
                    payload = None
                if payload is not None and (record := _decoded(payload)) is not None:
                    ident = (record.node, record.stamp, record.seq)
                    if ident in shown:
                        shown.discard(ident)
                    elif wanted.wants(record):
                        yield record
                if (line := router.check(time.monotonic())) is not None:
                    yield Notice(line)
        finally:
            if live is not None:
                live.undeclare()
