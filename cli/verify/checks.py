"""Each part of a specification measured on a running system through a ``turtlectl.Client``:
the interfaces (each topic present with its type, publisher and period; each service served
with its type) and every criterion.  Returns verdicts; prints nothing (``progress`` is told
what is being measured)."""

from __future__ import annotations

import statistics
from collections.abc import Callable

from turtlectl.cli.system.launchfile import LaunchPlan
from turtlectl.cli.verify import running
from turtlectl.cli.verify.goals import goals
from turtlectl.cli.verify.parameters import parameters
from turtlectl.cli.verify.report import Verdict
from turtlectl.cli.verify.spec import Criterion, Messages, NoErrors, Parameters, Period, RoundTrip, Spec, label
from turtlectl.cli.verify.timebase import Timebase
from turtlectl.messages.naming import names
from turtlectl.runtime.client.api import Client
from turtlectl.runtime.client.errors import TurtlectlError, Unreachable
from turtlectl.runtime.client.graph import Graph


def _arrivals(client: Client, key: str, count: int, within: float, clock: Timebase) -> list[tuple[float, float | None]]:
    """``count`` messages on ``key``, or as many as came within ``within`` s of ``clock``: each
    one's arrival time (``clock``'s s) and the publisher's ``stamp`` (s; None when its type has none)."""
    sub = client.subscribe(key)
    deadline = clock.now() + within
    times: list[tuple[float, float | None]] = []
    try:
        while len(times) < count and clock.now() < deadline:
            try:
                msg = sub.next(timeout=max(0.01, (deadline - clock.now()) / clock.factor))
            except TurtlectlError:
                break
            times.append((clock.now(), stamp_of(msg)))
    finally:
        sub.undeclare()
    return times


def stamp_of(message: object) -> float | None:
    """When ``message`` was published (s since the epoch), from its ``stamp`` (ns); None without one."""
    stamp = getattr(message, "stamp", 0)
    return stamp / 1e9 if isinstance(stamp, int) and stamp > 0 else None


def periods_of(times: list[tuple[float, float | None]], at: str) -> tuple[list[float], str]:
    """The periods (ms) between consecutive messages, by the publisher's stamps (``at`` =
    "publisher", when every message has one) or by arrival here; and which it was."""
    stamps = [s for _, s in times if s is not None]
    stamped = at == "publisher" and bool(times) and len(stamps) == len(times)
    points = stamps if stamped else [t for t, _ in times]
    periods = [(b - a) * 1000 for a, b in zip(points, points[1:], strict=False)]
    if stamped:
        return periods, "published"
    return periods, "arrived" if at == "subscriber" else "arrived: its messages have no stamp"


def _declared(
    want: str, owner: str, found: tuple[str, list[str]] | None, roles: tuple[str, str, str], absent: str
) -> tuple[str, str, list[str]]:
    """A declared topic or service against what the graph has (``found``: its type and its
    publishers or servers; None: absent): what is required, what was found, what is wrong.
    ``roles``: how to say the type, the owner in the table, the owner in a problem."""
    kind, by, wrong_by = roles
    required = want + (f" {by} {owner}" if owner else "")
    if found is None:
        return required, "absent", [absent]
    got, owners = found
    problems = [] if names(want, got) else [f"its {kind} is {got}"]  # a short name: the one type found there
    if owner and owner not in owners:
        problems.append(f"{wrong_by} {', '.join(owners) or 'nobody'}")
    return required, f"{got} {by} {', '.join(owners) or 'nobody'}", problems


def require_nodes(client: Client, graph: Graph, doing: str = "") -> None:
    """Unreachable (exit 3) when no node runs in ``graph``: a router alone is no system."""
    if not graph.nodes:
        hint = f" ({graph.hint})" if graph.hint else ""
        raise Unreachable(f"no nodes are running at {client.connect}{': ' + doing if doing else ''}{hint}")


def interfaces(client: Client, spec: Spec, graph: Graph, clock: Timebase) -> list[Verdict]:
    """Each declared topic and service against the live ``graph`` (and a topic's period)."""
    topics = {t.key: (t.type, t.publishers) for t in graph.topics}
    services = {s.key: (s.type, s.servers) for s in graph.services}
    out = []
    for t in spec.topic:
        found = topics.get(t.key)
        roles = ("type", "from", "published by")
        required, measured, problems = _declared(
            t.type, t.publisher, found, roles, "nothing publishes or subscribes to it"
        )
        if found is not None and t.period_ms is not None and not problems:
            periods, how = periods_of(_arrivals(client, t.key, 21, 20 * t.period_ms / 1000 + 5, clock), "publisher")
            if not periods:
                problems.append("no messages to measure its period")
            else:
                mean = statistics.fmean(periods)
                measured += f", mean period {mean:.1f} ms ({how})"
                required += f", every {t.period_ms:g} ± {t.tolerance_ms:g} ms"
                if abs(mean - t.period_ms) > t.tolerance_ms:
                    problems.append(f"mean period {mean:.1f} ms is {abs(mean - t.period_ms):.1f} ms off")
        out.append(Verdict(f"topic {t.key}", required, measured, not problems, "; ".join(problems)))
    for s in spec.service:
        roles = ("request type", "served by", "served by")
        required, measured, problems = _declared(s.request, s.server, services.get(s.key), roles, "nothing serves it")
        out.append(Verdict(f"service {s.key}", required, measured, not problems, "; ".join(problems)))
    return out


def _period(client: Client, c: Period, clock: Timebase) -> Verdict:
    times = _arrivals(client, c.key, c.samples + 1, (c.samples + 1) * c.period_ms / 1000 * 2 + 5, clock)
    required = f"{c.share:.0%} of {c.samples} periods within {c.period_ms:g} ± {c.tolerance_ms:g} ms ({c.at})"
    periods, how = periods_of(times, c.at)
    if len(periods) < c.samples:
        return Verdict(label(c), required, f"{len(periods)} periods", False, f"only {len(times)} messages arrived")
    within = sum(1 for p in periods if abs(p - c.period_ms) <= c.tolerance_ms) / len(periods)
    worst = max(periods, key=lambda p: abs(p - c.period_ms))
    measured = f"{within:.0%} within, mean {statistics.fmean(periods):.1f} ms, worst {worst:.1f} ms ({how})"
    why = "" if within >= c.share else f"{within:.0%} of periods within the tolerance, {c.share:.0%} required"
    return Verdict(label(c), required, measured, within >= c.share, why)


def _messages(client: Client, c: Messages, clock: Timebase) -> Verdict:
    before = {n.name: n.pid for n in client.nodes()}
    times = _arrivals(client, c.key, c.count, c.within_s, clock)
    after = {n.name: n.pid for n in client.nodes()}
    lost = sorted(n for n in before if after.get(n) != before[n])
    problems = []
    if len(times) < c.count:
        problems.append(f"only {len(times)} of {c.count} messages within {c.within_s:g} s")
        if not any(t.key == c.key and t.publishers for t in client.topics()):
            problems.append(f"nothing publishes {c.key}")
    if lost:
        problems.append(f"{', '.join(lost)} died or restarted meanwhile")
    required = f"{c.count} messages, the same {len(before)} node processes"
    return Verdict(
        label(c),
        required,
        f"{len(times)} messages, {len(before) - len(lost)} nodes unchanged",
        not problems,
        "; ".join(problems),
    )


def criterion(
    client: Client,
    c: Criterion,
    short: float | None = None,
    progress: Callable[[str], None] = lambda _: None,
    clock: Timebase | None = None,
    plan: LaunchPlan | None = None,
) -> Verdict:
    """One criterion measured (``short``: s, the longest a long one may run; None: its full time)
    on ``clock`` (the machine's by default; a system's simulated time: timebase.SimulatedTime);
    ``plan``: the launch file the system was started from, when verify knows it."""
    clock = clock or Timebase()
    if isinstance(c, Parameters):
        return parameters(client, c, plan)
    if isinstance(c, Period):
        return _period(client, c, clock)
    if isinstance(c, Messages):
        return _messages(client, c, clock)
    if isinstance(c, NoErrors):
        return running.no_errors(client, c, short, progress, clock)
    if isinstance(c, RoundTrip):
        return running.round_trip(client, c)
    return goals(client, c, clock)


def verify(
    client: Client,
    spec: Spec,
    progress: Callable[[str], None] = lambda _: None,
    short: float | None = None,
    clock: Timebase | None = None,
    plan: LaunchPlan | None = None,
) -> list[Verdict]:
    """Every interface and criterion of ``spec``, measured in the spec's order (``short``: s,
    the longest a long criterion may run, and its verdict says so; None: their full time) on
    ``clock`` (the machine's by default); ``plan``: the launch file the system was started
    from (the ``parameters`` criterion compares with it), None when verify does not know it."""
    clock = clock or Timebase()
    graph = client.graph()
    require_nodes(client, graph, "nothing to verify")
    progress("interfaces")
    out = interfaces(client, spec, graph, clock)
    for c in spec.criterion:
        progress(label(c))
        out.append(criterion(client, c, short, progress, clock, plan))
    return out
