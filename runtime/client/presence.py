"""A client's place in the graph: every client session (a command-line tool, a script's
``turtlectl.Client``) declares its presence once, in ``session.client_session``, as nodes declare
theirs, and its publishers and subscribers declared here are listed with it (``turtlectl list``,
``node list``, ``topic info``), as ROS 2 lists every participant.

A client is named ``<tool>-<pid>`` (``teleop-4242``; a second session of the same process
``teleop-4242-2``), its tool being the command that runs (teleop, goto, echo, record, plot, ...)
or ``python`` for a script's Client.  Its tokens live apart from the nodes'
(``@turtlectl/client_node/...``, ``@turtlectl/client_entity/...``), so a client never counts as
a node: not for the supervisor's readiness, not for a node's claims.  Nothing here prints.
"""

from __future__ import annotations

import itertools
import os
import socket
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # imported where used: cli.main sets the tool before any command runs, and stays quick
    import zenoh

    from turtlectl.messages.keys import ClientInfo

#: the tool this process runs (cli.main sets it to the command's name); a script's Client: python
_TOOL = ["python"]
_SESSIONS = itertools.count(1)
#: each open client session (by id) -> its presence
_PRESENT: dict[int, Presence] = {}


def set_tool(name: str) -> None:
    """Name the tool this process runs (``teleop``): its client sessions are listed as it."""
    _TOOL[:] = [name]


def tool() -> str:
    return _TOOL[0]


class Presence:
    """One client session's presence token and what it announces; ``undeclare`` withdraws all."""

    def __init__(self, session: zenoh.Session, domain: str = "", role: str | None = None) -> None:
        from turtlectl.messages.keys import ClientInfo, client_node_token

        #: the domain the session was opened in ("" for none), the role it logged in as (None: no login)
        self.domain, self.role = domain, role
        pid, n = os.getpid(), next(_SESSIONS)
        name = f"{tool()}-{pid}" + (f"-{n}" if n > 1 else "")
        self.info: ClientInfo = ClientInfo(
            name=name, pid=pid, host=socket.gethostname(), start_ns=time.time_ns(), tool=tool()
        )
        self._session = session
        self._token: Any = session.liveliness().declare_token(client_node_token(self.info))

    @property
    def name(self) -> str:
        return self.info.name

    def announce(self, role: str, type_name: str, key: str) -> Any:
        """The graph's token of this client's ``role`` ("pub", "sub") on ``key`` (a LivelinessToken)."""
        from turtlectl.messages.keys import EntityInfo, client_entity_token

        entity = EntityInfo(node=self.name, pid=self.info.pid, role=role, type_name=type_name or "unknown", key=key)
        return self._session.liveliness().declare_token(client_entity_token(entity))

    def undeclare(self) -> None:
        if self._token is not None:
            self._token.undeclare()
            self._token = None


def declare(session: zenoh.Session, domain: str = "", role: str | None = None) -> Presence:
    """Declare ``session``'s presence (client_session does, once per session), with the domain it
    was opened in and the role it logged in as (None: no login)."""
    presence = _PRESENT[id(session)] = Presence(session, domain, role)
    return presence


def withdraw(session: zenoh.Session) -> None:
    """Withdraw ``session``'s presence (client_session does, before it closes the session)."""
    presence = _PRESENT.pop(id(session), None)
    if presence is not None:
        presence.undeclare()


def of(session: zenoh.Session) -> Presence | None:
    """``session``'s presence, None for a session client_session did not open."""
    return _PRESENT.get(id(session))


class Announced:
    """A client's Zenoh publisher or subscriber and its graph token: ``undeclare`` withdraws
    both (idempotent); ``put`` publishes on a publisher."""

    def __init__(self, entity: Any, token: Any) -> None:
        self._entity, self._token = entity, token

    def put(self, payload: bytes) -> None:
        self._entity.put(payload)

    def undeclare(self) -> None:
        if self._entity is None:
            return
        if self._token is not None:
            self._token.undeclare()
        self._entity.undeclare()
        self._entity = self._token = None


def _token(session: zenoh.Session, role: str, type_name: str, key: str) -> Any:
    """The token of a publisher or subscriber on one plain key (a wildcard names no one topic:
    the client is listed, its subscription on ``**`` is not)."""
    presence = of(session)
    if presence is None or "*" in key:
        return None
    return presence.announce(role, type_name or type_of(key), key)


def type_of(key: str) -> str:
    """The full name of the type published on ``key`` if the wire contract names one, else ""."""
    from turtlectl.messages.codec import type_name
    from turtlectl.messages.keys import TOPICS, resolve

    namespace = key.partition("/")[0]
    found = TOPICS.get(key) or next((t for k, t in TOPICS.items() if resolve(k, namespace) == key), None)
    return "" if found is None else type_name(found)


def publisher(session: zenoh.Session, key: str, type_name: str, encoding: str = "") -> Announced:
    """A publisher on ``key`` of ``type_name`` (``turtlectl/Twist``), listed as this client's."""
    import zenoh

    pub = (
        session.declare_publisher(key, encoding=zenoh.Encoding(encoding))
        if encoding
        else session.declare_publisher(key)
    )
    return Announced(pub, _token(session, "pub", type_name, key))


def subscriber(session: zenoh.Session, key: str, callback: Callable[..., Any] | Any, type_name: str = "") -> Announced:
    """A subscriber on ``key`` (``callback``: a function or a zenoh handler), listed as this
    client's (``type_name`` "" when the key's type is not known: ``unknown``)."""
    sub = session.declare_subscriber(key, callback)
    return Announced(sub, _token(session, "sub", type_name, key))
