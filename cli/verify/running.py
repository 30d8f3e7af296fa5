"""The criteria of a specification about a system as it runs, measured through a
``turtlectl.Client``: nodes running a while without errors (``no_errors``: alive, the same
process, no log record at ERROR or worse; goals driven meanwhile when it lists them, through
cli.verify.driving) and message types round-tripping (``round_trip``)."""

from __future__ import annotations

from collections.abc import Callable

import msgspec

from turtlectl.cli.verify.driving import GoalDriver, goal_sequence
from turtlectl.cli.verify.report import Verdict
from turtlectl.cli.verify.spec import NoErrors, RoundTrip, label
from turtlectl.cli.verify.timebase import Timebase
from turtlectl.messages import decode, encode
from turtlectl.messages.codec import type_name
from turtlectl.messages.keys import NodeDetails
from turtlectl.runtime.client.api import Client
from turtlectl.runtime.client.errors import TurtlectlError
from turtlectl.runtime.client.graph import under

#: s: how often the nodes alive are looked at while a no_errors criterion runs
LOOK_EVERY = 1.0
#: s: how often progress is told while it runs
TELL_EVERY = 30.0


def _duration(c: NoErrors, short: float | None) -> tuple[float, str]:
    """How long it runs (s) and, when ``short`` cut it, what the table says about that."""
    full = c.minutes * 60.0
    if short is None or short >= full:
        return full, ""
    return short, f"; shortened to {short:g} s (--short)"


def _details(client: Client, names: list[str]) -> dict[str, NodeDetails]:
    out = {}
    for name in names:
        try:
            out[name] = client.node_info(name)
        except TurtlectlError:
            continue  # gone meanwhile: seen as not alive
    return out


def no_errors(
    client: Client,
    c: NoErrors,
    short: float | None,
    progress: Callable[[str], None] = lambda _: None,
    clock: Timebase | None = None,
) -> Verdict:
    clock = clock or Timebase()
    duration, cut = _duration(c, short)
    driving = ", while goals are driven" if c.goals or c.random_goals else ""
    required = f"{c.minutes:g} min alive, same process, no ERROR records{driving}{cut}"
    alive = {n.name: n.pid for n in client.nodes()}
    if c.node and c.node not in alive:
        running = ", ".join(sorted(alive)) or "none"
        return Verdict(label(c), required, "not running", False, f"no node named {c.node} runs (running: {running})")
    names = [c.node] if c.node else sorted(alive)
    before = _details(client, names)
    driver = None
    if c.goals or c.random_goals:
        try:
            goals = goal_sequence(c, client.world())
        except ValueError as exc:
            return Verdict(label(c), required, "no goals driven", False, str(exc))
        driver = GoalDriver(client, goals).start()
    events: dict[str, str] = {}  # node -> what happened to it first (stopped, restarted)
    started = clock.now()
    told = started
    try:
        while (now := clock.now()) - started < duration:
            clock.sleep(min(LOOK_EVERY, duration - (now - started)))
            seen = {n.name: n.pid for n in client.nodes()}
            at = clock.now() - started
            for name in names:
                if name in events or name not in before:
                    continue
                if name not in seen:
                    events[name] = f"{name} stopped at {at:.0f} s"
                elif seen[name] != before[name].pid:
                    events[name] = f"{name} restarted at {at:.0f} s (pid {before[name].pid} -> {seen[name]})"
            if clock.now() - told >= TELL_EVERY:
                told = clock.now()
                progress(f"{label(c)}: {told - started:.0f} of {duration:g} s")
    finally:
        outcomes = driver.stop() if driver is not None else None
    after = _details(client, [n for n in names if n not in events])
    problems = [events[n] for n in names if n in events]
    problems += [f"{n} did not say what it is" for n in names if n not in before]
    errors = 0
    for name, now_details in after.items():
        if name not in before or now_details.pid != before[name].pid:
            continue
        new = now_details.errors - before[name].errors
        errors += max(0, new)
        if new > 0:
            problems.append(f"{name} logged {new} error{'s' * (new > 1)} (the last: {now_details.last_error})")
    measured = f"{clock.now() - started:.0f} s, {len(names)} node{'s' * (len(names) != 1)}, {errors} errors"
    measured += f", {len(events)} stopped or restarted"
    if outcomes is not None:
        measured += f"; {outcomes.summary()}"
        problems += outcomes.problems()
    return Verdict(label(c), required, measured, not problems, "; ".join(problems))


def _published(client: Client) -> list[str]:
    return sorted(t.key for t in client.topics() if t.publishers and not under(t.key))


def round_trip(client: Client, c: RoundTrip) -> Verdict:
    """Each key's first message (within ``within_s``): decoded strictly as its type, encoded and
    decoded again to the same bytes.  Named keys must have one; of every published topic (no
    ``keys``), those silent meanwhile (feedback, commands while idle) are listed, not failed."""
    keys = c.keys or _published(client)
    problems, types, received, silent = [], set(), 0, []
    for key in keys:
        sub = client.subscribe(key)
        try:
            message = sub.next(timeout=c.within_s)
        except TurtlectlError:
            if sub.skipped:
                problems.append(f"{key}: none decoded; {sub.skipped} skipped, the last: {sub.last_problem}")
            elif c.keys:
                problems.append(f"{key}: no message within {c.within_s:g} s")
            else:
                silent.append(key)
            continue
        finally:
            sub.undeclare()
        kind = type(message)
        types.add(type_name(kind))
        received += 1
        if sub.skipped:
            problems.append(f"{key}: {sub.skipped} payloads did not decode, the last: {sub.last_problem}")
        payload = encode(message)
        try:
            again = decode(payload, kind)
        except msgspec.DecodeError as exc:
            problems.append(f"{key}: {type_name(kind)} does not decode what it encodes: {exc}")
            continue
        if encode(again) != payload:
            problems.append(f"{key}: {type_name(kind)} changes on a round trip")
    if not keys:
        problems.append("no topic is published")
    required = f"{len(keys)} keys: decode strictly, encode and decode back the same"
    measured = f"{len(types)} types in messages on {received} of {len(keys)} keys"
    measured += f" (silent within {c.within_s:g} s: {', '.join(silent)})" if silent else ""
    return Verdict(label(c), required, measured, not problems, "; ".join(problems))
