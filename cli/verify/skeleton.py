"""A specification's skeleton from a running system (``turtlectl spec from-system``): the live
graph, each node's parameters, and each published topic's period measured over a short
window, from the messages' own stamps (as published) or, for a type without one, from their
arrivals here.  The writing is pure (cli.verify.document); this module only measures,
through a ``Client``."""

from __future__ import annotations

import statistics
import threading
import time
from typing import Any

from turtlectl.cli.verify import document
from turtlectl.cli.verify.checks import periods_of, require_nodes, stamp_of
from turtlectl.cli.verify.spec import Spec
from turtlectl.runtime.client.api import Client
from turtlectl.runtime.client.errors import TurtlectlError
from turtlectl.runtime.client.graph import Graph, without_node_services

#: s of messages a period is measured over
WINDOW = 2.0
#: the fewest messages a period is measured from (a slower topic gets no period)
LEAST = 4
#: a topic's tolerance, as a share of its period, and at least FLOOR ms (a 62.5 Hz pose's
#: 1.6 ms would fail on the scheduling of a busy machine: the skeleton is a start to edit)
TOLERANCE = 0.1
FLOOR = 5.0


def period_of(times: list[tuple[float, float | None]]) -> tuple[float, float] | None:
    """A topic's period and tolerance (ms, as a specification states them) from its messages'
    arrivals and stamps (s; a stamp None when the type has none): between the stamps when
    every message has one, else between the arrivals; None from fewer than LEAST messages.
    The typical gap (the median) is the period: one stall of the publisher in the window made
    the mean of a 64 ms topic 72 ms, and the skeleton then failed its own system."""
    if len(times) < LEAST:
        return None
    gaps, _ = periods_of(times, "publisher")
    typical = statistics.median(gaps)
    if typical <= 0:
        return None
    period = document.rounded_period(typical)
    return period, max(FLOOR, round(period * TOLERANCE, 2))


def measure(client: Client, seconds: float = WINDOW) -> tuple[Graph, dict[str, tuple[float, float]]]:
    """The live graph (without each node's own services) and each published topic's period
    and tolerance (ms), measured over ``seconds`` s at once."""
    graph = without_node_services(client.graph())
    require_nodes(client, graph)
    lock = threading.Lock()
    seen: dict[str, list[tuple[float, float | None]]] = {}
    subscriptions = []

    def recorder(key: str):  # noqa: ANN202 - a callback on Zenoh's thread
        def record(message: object) -> None:
            with lock:
                seen[key].append((time.monotonic(), stamp_of(message)))

        return record

    try:
        for topic in graph.topics:
            if topic.publishers:
                seen[topic.key] = []
                subscriptions.append(client.subscribe(topic.key, recorder(topic.key)))
        time.sleep(seconds)  # the measuring window itself
    finally:
        for sub in subscriptions:
            sub.undeclare()
    with lock:
        periods = {key: p for key, times in seen.items() if (p := period_of(times)) is not None}
    return graph, periods


def running_params(client: Client, graph: Graph) -> dict[str, dict[str, Any]]:
    """Each node's parameters as it runs with them (as ``param dump`` reads them); a node that
    does not answer is left out."""
    out = {}
    for node in graph.nodes:
        try:
            out[node.name] = client.params(node.name)
        except TurtlectlError:
            continue  # no parameters to state (not a turtlectl node, or gone meanwhile)
    return out


def from_system(client: Client, seconds: float = WINDOW) -> Spec:
    """The skeleton of a specification of the system ``client`` talks to."""
    graph, periods = measure(client, seconds)
    return document.skeleton(graph, periods, running_params(client, graph))
