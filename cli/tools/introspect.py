"""``turtlectl node info``, ``topic info`` and ``log-level``: one node or one topic in detail,
as ``ros2 node info`` / ``ros2 topic info -v``, from the liveliness graph and the node's own
answers (``turtlectl/nodes/<name>``, ``turtlectl/params/<name>``).  Prints nothing."""

from __future__ import annotations

import time
from typing import Any

import msgspec

from turtlectl.cli import args
from turtlectl.cli.tools.params import TIMEOUT  # s a node has to answer
from turtlectl.messages import Ack, SetLogLevel
from turtlectl.messages.keys import NodeDetails, log_level_key, node_key
from turtlectl.runtime.client import answers
from turtlectl.runtime.client.answers import parse_details
from turtlectl.runtime.client.errors import BadInput, Failed
from turtlectl.runtime.client.graph import Graph
from turtlectl.runtime.client.services import NoAnswer, NobodyServes, call_service

RATE_WINDOW = 1.0  # s over which `topic info -v` measures the rate


class Endpoint(msgspec.Struct):
    key: str
    type: str


class NodeReport(msgspec.Struct):
    """One node: what it is, and what it publishes, subscribes to and serves."""

    name: str
    kind: str
    pid: int
    host: str
    uptime: float  # s
    log_level: str
    publishers: list[Endpoint]
    subscribers: list[Endpoint]
    services: list[Endpoint]
    parameters: dict[str, Any]
    errors: int = 0  # records at ERROR or worse logged since it started
    last_error: str = ""  # the last one's message
    use_sim_time: bool = False  # its time is the simulator's clock


def _no_node(node: str, graph: Graph, domain: str) -> NobodyServes:
    from turtlectl.runtime.client.answers import no_node

    return no_node(node, [n.name for n in graph.nodes], domain, graph.hint)


def _asked(connect: str, domain: str, node: str, key: str, request: Any, what: str) -> list[Any]:
    """``node``'s answers on ``key``; one that runs but does not answer ``what`` is said to run
    (params.silent: Silent, exit 3), one that does not run is named with those that do."""
    from turtlectl.cli.tools.params import silent

    try:
        return list(call_service(connect, domain, key, request, TIMEOUT))
    except NobodyServes as exc:
        raise silent(connect, domain, node, what, exc) from None
    except NoAnswer as exc:
        if exc.answered:
            raise
        raise silent(connect, domain, node, what, exc) from None


def _details(connect: str, domain: str, node: str) -> NodeDetails:
    return parse_details(node, _asked(connect, domain, node, node_key(node), b"", "what it is"))


def node_report(connect: str, domain: str, node: str) -> NodeReport:
    """Node ``node`` in detail (NobodyServes, exit 3, naming the running nodes if none is called so)."""
    from turtlectl.cli.tools import params, topics

    graph = topics.graph(connect, domain)
    client = next((c for c in graph.clients if c.name == node), None)
    if client is not None:  # listed by `node list`, but it serves nothing to ask
        raise BadInput(
            f"{node} is a client ({client.tool}, pid {client.pid}, host {client.host}), not a node: "
            f"`turtlectl list` shows what it publishes and subscribes to"
        )
    if node not in {n.name for n in graph.nodes}:
        raise _no_node(node, graph, domain)
    details = _details(connect, domain, node)
    return NodeReport(
        name=node,
        kind=details.kind,
        pid=details.pid,
        host=details.host,
        uptime=max(0.0, (time.time_ns() - details.start_ns) / 1e9),
        log_level=details.log_level,
        publishers=[Endpoint(t.key, t.type) for t in graph.topics if node in t.publishers],
        subscribers=[Endpoint(t.key, t.type) for t in graph.topics if node in t.subscribers],
        services=[Endpoint(s.key, s.type) for s in graph.services if node in s.servers],
        parameters=params.fetch(connect, domain, node),
        errors=details.errors,
        last_error=details.last_error,
        use_sim_time=details.use_sim_time,
    )


def _rows(endpoints: list[Endpoint]) -> list[str]:
    width = max([len(e.key) for e in endpoints] + [10])
    return [f"  {e.key:{width}s} {e.type}" for e in endpoints] or ["  (none)"]


def node_text(report: NodeReport) -> str:
    from turtlectl.cli.tools import params

    lines = [
        f"{report.name}  kind {report.kind}, pid {report.pid}, host {report.host}, "
        f"up {report.uptime:.1f} s, log level {report.log_level}"
        + (", use_sim_time (its time is the simulator's clock)" if report.use_sim_time else ""),
        *([f"ERRORS {report.errors} logged, the last: {report.last_error}"] if report.errors else []),
        "PUBLISHERS",
        *_rows(report.publishers),
        "SUBSCRIBERS",
        *_rows(report.subscribers),
        "SERVICES",
        *_rows(report.services),
        "PARAMETERS",
    ]
    for name in params.names(report.parameters):
        lines.append(f"  {name} = {msgspec.json.encode(answers.value(report.parameters, report.name, name)).decode()}")
    return "\n".join(lines)


class TopicEnd(msgspec.Struct):
    node: str  # a node's name, or a client's (teleop-4242)
    pid: int
    host: str
    tool: str = ""  # a client's tool (teleop, echo, record, python, ...); "" for a node


class TopicReport(msgspec.Struct):
    """One topic: its type, who publishes and who subscribes, and (``-v``) its rate."""

    key: str
    type: str
    publishers: list[TopicEnd]
    subscribers: list[TopicEnd]
    rate: float | None = None  # Hz over RATE_WINDOW s (None: not measured)
    messages: int | None = None  # received while measuring


def topic_report(connect: str, domain: str, key: str, verbose: bool) -> TopicReport:
    """Topic ``key`` from the live graph; with ``verbose`` its rate measured over a second.
    A key no node publishes or subscribes to is NobodyServes (exit 3) naming the known topics."""
    from turtlectl.cli.tools import topics
    from turtlectl.runtime.client.session import check_key

    key = check_key(key)
    graph = topics.graph(connect, domain)
    row = next((t for t in graph.topics if t.key == key), None)
    service = next((s for s in graph.services if s.key == key), None)
    if row is None and service is not None:
        raise BadInput(
            f"{key} is a service ({service.type}, served by {', '.join(service.servers)}), not a topic: "
            f"`turtlectl call {key} JSON` calls it"
        )
    if row is None:
        known = ", ".join(t.key for t in graph.topics) or "none"
        raise NobodyServes(f"no node publishes or subscribes to {key!r} (topics: {known})")
    nodes = {n.name: n for n in [*graph.nodes, *graph.clients]}

    def end(name: str) -> TopicEnd:
        n = nodes.get(name)
        return TopicEnd(node=name, pid=n.pid if n else 0, host=n.host if n else "", tool=n.tool if n else "")

    report = TopicReport(
        key=key,
        type=row.type,
        publishers=[end(n) for n in row.publishers],
        subscribers=[end(n) for n in row.subscribers],
    )
    if verbose:
        report.messages, report.rate = _measure(connect, domain, key)
    return report


def _measure(connect: str, domain: str, key: str) -> tuple[int, float]:
    """Messages received on ``key`` over RATE_WINDOW s, and their rate (Hz, from the first to
    the last arrival; 0 below two messages)."""
    import queue

    from turtlectl.runtime.client.session import client_session

    arrivals: queue.SimpleQueue[float] = queue.SimpleQueue()
    with client_session(connect, domain) as session:
        sub = session.declare_subscriber(key, lambda _sample: arrivals.put(time.monotonic()))
        time.sleep(RATE_WINDOW)  # the measuring window itself, not a wait for readiness
        sub.undeclare()
    times = []
    while not arrivals.empty():
        times.append(arrivals.get())
    rate = (len(times) - 1) / (times[-1] - times[0]) if len(times) >= 2 and times[-1] > times[0] else 0.0
    return len(times), rate


def topic_text(report: TopicReport) -> str:
    def ends(items: list[TopicEnd]) -> list[str]:
        return [f"  {e.node} ({f'client: {e.tool}, ' if e.tool else ''}pid {e.pid}, host {e.host})" for e in items] or [
            "  (none)"
        ]

    lines = [f"{report.key}  type {report.type}"]
    if report.rate is not None:
        lines.append(f"rate {report.rate:.2f} Hz ({report.messages} messages in {RATE_WINDOW:g} s)")
    lines += [
        f"PUBLISHERS ({len(report.publishers)})",
        *ends(report.publishers),
        f"SUBSCRIBERS ({len(report.subscribers)})",
        *ends(report.subscribers),
    ]
    return "\n".join(lines)


def set_log_level(connect: str, domain: str, node: str, level: str) -> str:
    """Make ``node`` log ``level`` and above from now on; returns its answer."""
    level = args.log_level(level)
    answers = _asked(connect, domain, node, log_level_key(node), SetLogLevel(level=level), "to set its log level")
    acks = [a for a in answers if isinstance(a, Ack)]
    if not acks:
        raise Failed(f"{node} did not confirm its log level")
    return acks[-1].detail


def nodes_named(connect: str, domain: str, selector: str) -> list[str] | None:
    """The running nodes ``selector`` names (cli.selection: a name, namespace, turtle or glob);
    None when it names one node as its name does, or no node and is no glob: the caller asks
    that name, and a node that does not run is said as for any name (with the running ones)."""
    from turtlectl.cli.selection import is_glob, selected
    from turtlectl.runtime.client.answers import no_node
    from turtlectl.runtime.client.session import client_session, live_graph

    with client_session(connect, domain) as session:
        graph = live_graph(session)
    running = [n.name for n in graph.nodes if not n.domain]
    chosen = selected([selector], running)
    if chosen == [selector] or (not chosen and not is_glob(selector)):
        return None
    if not chosen:
        raise no_node(selector, running, domain, graph.hint)
    return chosen


def set_log_levels(connect: str, domain: str, selector: str, level: str) -> str:
    """Make every running node ``selector`` names (``nodes_named``) log ``level`` and above from
    now on; their answers, one line each (a node's own answer alone when it is named)."""
    level = args.log_level(level)
    chosen = nodes_named(connect, domain, selector)
    if chosen is None:
        return set_log_level(connect, domain, selector, level)
    return "\n".join(f"{node}: {set_log_level(connect, domain, node, level)}" for node in chosen)
