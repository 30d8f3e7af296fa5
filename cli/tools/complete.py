"""Shell completion of live names: the topics, nodes, turtles, goal services and parameters of
the running system, asked when the shell asks (``turtlectl echo ro<TAB>``).

Completion must never get in the way: each function answers in a fraction of a second (0.3-0.4 s
against a running system), and with nothing (an empty list, no message, no exit code) when no
system runs, the router refuses the login or anything else goes wrong: the shell then offers
nothing, as it does for an unknown word.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator

from turtlectl.runtime.endpoint import CONNECT_ENV, DEFAULT_ENDPOINT, default_domain


def _connect(params: dict[str, object]) -> str:
    """The endpoint the command line being completed names (--connect, else the environment's)."""
    given = params.get("connect")
    return str(given) if given else os.environ.get(CONNECT_ENV, DEFAULT_ENDPOINT)


@contextlib.contextmanager
def _quietly() -> Iterator[None]:
    """Whatever goes wrong, the completion is empty and nothing is printed (a shell shows a
    completion's output as candidates)."""
    try:
        yield
    except BaseException:  # noqa: BLE001 - a completion never fails, it offers nothing
        pass


def _domain(params: dict[str, object]) -> str:
    """The domain the command line being completed names (--domain, else the environment's)."""
    given = params.get("domain")
    return str(given) if given else default_domain()


def _graph(params: dict[str, object]):  # -> Graph | None
    from turtlectl.runtime.client import session as client
    from turtlectl.runtime.client.session import live_graph

    with client.client_session(_connect(params), _domain(params)) as session:
        return live_graph(session)


def _starting(names: list[str], incomplete: str) -> list[str]:
    """The names beginning with ``incomplete``; the runtime's own (``turtlectl/...``: every node's
    parameters, node info, log) only once ``incomplete`` begins so, as ``list`` hides them without --all."""
    own = incomplete.startswith("turtlectl")
    return sorted(
        {name for name in names if name.startswith(incomplete) and (own or not name.startswith("turtlectl/"))}
    )


def topics(params: dict[str, object], incomplete: str) -> list[str]:
    """The running system's topic keys starting with ``incomplete``."""
    with _quietly():
        graph = _graph(params)
        return _starting([row.key for row in graph.topics], incomplete)
    return []


def services(params: dict[str, object], incomplete: str) -> list[str]:
    """Its service keys (queryables) starting with ``incomplete``."""
    with _quietly():
        graph = _graph(params)
        return _starting([row.key for row in graph.services], incomplete)
    return []


def goal_services(params: dict[str, object], incomplete: str) -> list[str]:
    """Its goal services' keys starting with ``incomplete``."""
    with _quietly():
        graph = _graph(params)
        return _starting([row.key for row in graph.goals], incomplete)
    return []


def nodes(params: dict[str, object], incomplete: str) -> list[str]:
    """Its nodes' names (and their namespaces, which name all their nodes) starting with ``incomplete``."""
    with _quietly():
        graph = _graph(params)
        names = [row.name for row in graph.nodes]
        namespaces = [name.rsplit("/", 1)[0] for name in names if "/" in name]
        return _starting(names + namespaces, incomplete)
    return []


def turtles(params: dict[str, object], incomplete: str) -> list[str]:
    """The turtles' names starting with ``incomplete``: each ``NAME/pose`` the simulator publishes."""
    with _quietly():
        graph = _graph(params)
        poses = [row.key.removesuffix("/pose") for row in graph.topics if row.key.endswith("/pose")]
        return _starting([name for name in poses if "/" not in name], incomplete)
    return []


def parameters(params: dict[str, object], incomplete: str) -> list[str]:
    """The parameter names of the node the command line names (its NODE argument) starting with
    ``incomplete``; none without a node."""
    node = params.get("node")
    if not node or any(ch in str(node) for ch in "*?["):
        return []
    with _quietly():
        from turtlectl.cli.tools import params as node_params

        return _starting(node_params.names(node_params.fetch(_connect(params), _domain(params), str(node))), incomplete)
    return []
