"""Routers: the one way turtlectl opens a router (``launch`` and ``router``) or joins one
(``launch --connect``), and tells a busy port from other failures.

``turtlectl router`` is a Zenoh router alone, for systems whose nodes join with ``launch
--connect`` (on other hosts, or to survive a router restart), as rmw_zenoh's ``rmw_zenohd``.
"""

from __future__ import annotations

import signal
import socket
import threading
from collections.abc import Callable
from typing import Any

import zenoh

from turtlectl.cli.errors import CannotStart, Unreachable
from turtlectl.runtime.config import Credentials
from turtlectl.runtime.session import client_config, close_session, open_session, router_config, zenoh_reason

JOIN_TIMEOUT = 3.0  # s to reach the router that ``launch --connect`` joins


def free_port_near(port: int, host: str = "127.0.0.1") -> int:
    """The first port after ``port`` (wrapping below it at the top) that ``host`` can listen on now."""
    candidates = [p for p in range(port + 1, min(port + 50, 65536))] + list(range(port - 1, max(port - 50, 0), -1))
    for candidate in candidates:
        with socket.socket() as probe:
            try:
                probe.bind((host.strip("[]"), candidate))
            except OSError:
                continue
            return candidate
    return port + 1 if port < 65535 else port - 1


def port_in_use(port: int, command: str, host: str = "127.0.0.1") -> str:
    """Why a listen failed on a busy port, and the command that avoids it (with a port that is free now)."""
    other = free_port_near(port, host)
    if command == "launch":
        how = f'.venv/bin/turtlectl launch --port {other} (or make run ARGS="--port {other}")'
    else:
        how = f".venv/bin/turtlectl {command} --port {other}"
    return f"the port is already in use (another `turtlectl {command}`?); choose another: {how}"


def open_router(
    port: int,
    host: str,
    command: str,
    users_file: str | None = None,
    access: dict[str, Any] | None = None,
    tls: str | None = None,
) -> zenoh.Session:
    """A router session listening on tcp/``host``:``port`` (with ``users_file``: only for the
    sessions that log in as one of its users), or CannotStart saying why (a busy port names the
    ``command`` to type with a free one)."""
    try:
        return open_session(router_config(port, host, users_file, access, tls))
    except zenoh.ZError as exc:
        reason = port_in_use(port, command, host) if "in use" in str(exc) else zenoh_reason(exc)
        raise CannotStart(f"cannot listen on {'tls' if tls else 'tcp'}/{host}:{port}: {reason}") from None


def join_router(endpoint: str, login: Credentials | None = None, timeout: float = JOIN_TIMEOUT) -> zenoh.Session:
    """A client session of the router at ``endpoint`` (logged in with ``login``, if given), or
    Unreachable after ``timeout`` s."""
    try:
        return open_session(client_config(endpoint, timeout, credentials=login))
    except zenoh.ZError:
        raise Unreachable(f"no router at {endpoint} to join") from None


def run_router(port: int, host: str, on_ready: Callable[[], None]) -> None:
    """Serve as a router on tcp/``host``:``port`` until SIGINT/SIGTERM; ``on_ready()`` once listening."""
    stop = threading.Event()
    session = open_router(port, host, "router")
    previous = {sig: signal.signal(sig, lambda *_: stop.set()) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        on_ready()
        while not stop.wait(0.2):
            pass
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        close_session(session)
