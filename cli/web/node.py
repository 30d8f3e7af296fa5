"""The web page's node (``run = "web"`` in a launch file, or ``turtlectl web``): serves the page on
``host``:``port`` and talks to the system through a client session of its own, logged in with its
role on a ``--secure`` system (cli.web.server, cli.web.hub, cli.web.actions).

A node of the command line's layer, started as a user's node class is (exec, runtime.__main__):
it does what the commands do (``param set``'s checks are cli.tools.params'), which the node kinds
below the command line may not import.
"""

from __future__ import annotations

import threading
import time

import msgspec

from turtlectl.cli.web import protocol
from turtlectl.cli.web.actions import Actions
from turtlectl.cli.web.hub import Hub
from turtlectl.cli.web.server import WebServer, is_loopback
from turtlectl.nodes.params import WEB_INTERFACE, WebParams
from turtlectl.runtime import Node
from turtlectl.runtime.client.api import Client
from turtlectl.runtime.client.errors import CannotStart, TurtlectlError
from turtlectl.runtime.client.session import logged_in_as, router_lost

KIND_UNKNOWN = "?"


class Web:
    Params = WebParams
    Claims = ()  # two pages may serve one system (on two ports)
    Interface = WEB_INTERFACE

    def __init__(self, node: Node[WebParams]):
        self.node = node
        p = node.params
        role = p.role
        self.client = Client(node.connect, node.domain, role=role)
        secure = logged_in_as(self.client.session) is not None
        allowed = protocol.can(role, secure)
        world = self.client.world()
        self.kinds: dict[tuple[str, int], str] = {}
        hello = {
            "role": role if secure else "",
            "secure": secure,
            "can": allowed,
            "world": msgspec.to_builtins(world),
            "limits": msgspec.to_builtins(node.limits),
            "server": node.name,
            "trail": p.trail,
            "drive_repeat": protocol.DRIVE_REPEAT,
        }
        self.server = WebServer(
            p.host,
            p.port,
            Actions(self.client, self._outcome, lambda turtle: self.server.hub.goal_running(turtle)),
            lambda wake: Hub(self.client.session, wake),
            hello,
            role,
            node.log,
            self.graph_frame,
            lambda: router_lost(self.client.session),
        )
        try:
            self.server.start()
        except OSError as exc:
            self.client.close()
            raise CannotStart(page_port_problem(p.host, p.port, exc)) from None
        self.server.hub.viewed = False  # until a page opens
        self.server.hub.start()
        threading.Thread(target=self._history, name="web log history", daemon=True).start()
        node.on_shutdown(self.close)
        where = "this host only" if is_loopback(p.host) else "every host that reaches it"
        rights = f", logged in as {role}" if secure else ""
        node.log.info("the page: http://%s:%d/ (%s%s)", _url_host(p.host), p.port, where, rights)

    def _history(self) -> None:
        """The nodes' recent log records, for the log panel of a page that opens now."""
        from turtlectl.cli.tools.log import recent

        try:
            self.server.hub.history(recent(self.client.session))
        except Exception as exc:  # the panel shows what comes from now on
            self.node.log.warning("could not read the nodes' recent log records: %s", exc)

    def close(self) -> None:
        self.server.stop()
        self.server.hub.close()
        self.client.close()

    def _outcome(self, frame: bytes) -> None:
        self.server.broadcast(frame)

    def graph_frame(self) -> bytes | None:
        """The ``graph`` frame: nodes (name, kind, pid, host, uptime, namespace), other clients,
        topics (key, type, rate Hz, publishers, subscribers), the goal services served (keys)."""
        try:
            graph = self.client.graph()
        except TurtlectlError:
            return None
        rates = self.server.hub.rates()
        nodes = [{**msgspec.to_builtins(n), "kind": self._kind(n.name, n.pid)} for n in graph.nodes]
        topics = []
        listed = set()
        for row in graph.topics:
            rate, seen = rates.get(row.key, (0.0, ""))
            topics.append({**msgspec.to_builtins(row), "type": row.type or seen, "rate": rate})
            listed.add(row.key)
        for key, (rate, seen) in rates.items():  # published by someone the graph does not list (a raw session)
            if key not in listed and not key.startswith("@"):
                topics.append({"key": key, "type": seen, "rate": rate, "publishers": [], "subscribers": []})
        clients = [msgspec.to_builtins(c) for c in graph.clients]
        goals = sorted(row.key for row in graph.goals)
        return protocol.encode(
            "graph",
            nodes=nodes,
            clients=clients,
            topics=sorted(topics, key=lambda t: t["key"]),
            goals=goals,
            time=time.time(),
        )

    def _kind(self, name: str, pid: int) -> str:
        """A node's kind (asked once per process: a node restarted is asked again)."""
        kind = self.kinds.get((name, pid))
        if kind is None:
            try:
                kind = self.client.node_info(name).kind
            except TurtlectlError:
                kind = KIND_UNKNOWN
            self.kinds[(name, pid)] = kind
        return kind


def page_port_problem(host: str, port: int, error: OSError) -> str:
    """Why the page cannot listen on ``host``:``port``, and what to do."""
    import errno

    if error.errno == errno.EADDRINUSE or "in use" in str(error):
        return (
            f"cannot serve the page: port {port} on {host} is in use (another turtlectl web?); choose another:"
            " turtlectl web --port, launch --web, or the web node's port parameter"
        )
    return f"cannot serve the page on {host}:{port}: {error.strerror or error}"


def _url_host(host: str) -> str:
    return "127.0.0.1" if host in ("0.0.0.0", "") else host
