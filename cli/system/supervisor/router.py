"""Routers: the one way turtlectl opens a router (``launch`` and ``router``) or joins one
(``launch --connect``), and tells a busy port from other failures.

``turtlectl router`` is a Zenoh router alone, for systems whose nodes join with ``launch
--connect`` (on other hosts, or to survive a router restart), as rmw_zenoh's ``rmw_zenohd``.
"""

from __future__ import annotations

import os
import shlex
import shutil
import signal
import socket
import sys
import threading
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import zenoh

from turtlectl.cli import command_of
from turtlectl.runtime.client.errors import CannotStart, Unreachable
from turtlectl.runtime.config import Credentials
from turtlectl.runtime.session import (
    client_config,
    close_session,
    listen_hosts,
    open_session,
    router_config,
    zenoh_reason,
)

JOIN_TIMEOUT = 3.0  # s to reach the router that ``launch --connect`` joins
MAKE_RUN_ENV = "TURTLECTL_MAKE_RUN"  # set by the Makefile's `run`: its command line is `make run ARGS=...`
MAKE_WEB_ENV = "TURTLECTL_MAKE_WEB"  # set by the Makefile's `run` to its WEB: it adds `--web WEB` after ARGS


def free_port_near(port: int, host: str = "127.0.0.1") -> int:
    """The first port after ``port`` (wrapping below it at the top) that a router told to listen
    on ``host`` can listen on now: on every address it listens on (``listen_hosts``: loopback too)."""
    candidates = [p for p in range(port + 1, min(port + 50, 65536))] + list(range(port - 1, max(port - 50, 0), -1))
    addresses = [h.strip("[]") for h in listen_hosts(host)]
    for candidate in candidates:
        if all(_bindable(address, candidate) for address in addresses):
            return candidate
    return port + 1 if port < 65535 else port - 1


def _bindable(address: str, port: int) -> bool:
    with socket.socket(socket.AF_INET6 if ":" in address else socket.AF_INET) as probe:
        try:
            probe.bind((address, port))
        except OSError:
            return False
        return True


def invoked_as(program: str, path: str | None = None) -> list[str]:
    """The program name to type again, from ``program`` (``argv[0]``): a shell that found it on
    ``path`` (``$PATH``) passes its full path, given back as the bare name; ``python -m
    turtlectl.cli`` as that; any other path (``.venv/bin/turtlectl``) as it was typed."""
    if Path(program).name == "__main__.py":
        return ["python", "-m", "turtlectl.cli"]
    name = Path(program).name
    found = shutil.which(name, path=path if path is not None else os.environ.get("PATH", os.defpath))
    if found is not None and os.path.abspath(found) == os.path.abspath(program):
        return [name]
    return [program]


def with_port(args: Sequence[str], port: int) -> list[str]:
    """``args`` (a command line's words) with ``--port`` set to ``port``: replaced where given
    (``--port N`` or ``--port=N``), appended otherwise."""
    words = list(args)
    for i, word in enumerate(words):
        if word == "--port" and i + 1 < len(words):
            return [*words[: i + 1], str(port), *words[i + 2 :]]
        if word.startswith("--port="):
            return [*words[:i], f"--port={port}", *words[i + 1 :]]
    return [*words, "--port", str(port)]


def retyped(argv: Sequence[str], command: str, port: int, environ: Mapping[str, str] | None = None) -> str:
    """The command line ``argv`` (``sys.argv`` of a ``command``) as the user typed it, its
    launch file and every argument kept, with ``--port port``; under ``make run`` (which sets
    ``MAKE_RUN_ENV``) the ``make run ARGS=...`` to type (without the ``--web`` make adds itself). Without ``argv`` (or one of another command):
    ``turtlectl command --port port``."""
    env = os.environ if environ is None else environ
    if len(argv) < 2 or command_of(list(argv[1:])) != command:
        return shlex.join(["turtlectl", command, "--port", str(port)])
    words = with_port(argv[1:], port)
    if env.get(MAKE_RUN_ENV) and words[0] == "launch":
        web = env.get(MAKE_WEB_ENV, "")
        if web and words[-2:] == ["--web", web]:  # make's own, not the user's ARGS
            words = words[:-2]
        return "make run ARGS=" + shlex.quote(shlex.join(words[1:]))
    return shlex.join([*invoked_as(argv[0], env.get("PATH", os.defpath)), *words])


def port_in_use(port: int, command: str, host: str = "127.0.0.1", argv: Sequence[str] | None = None) -> str:
    """Why a listen failed on a busy port, and the command that avoids it: the command line
    ``argv`` as typed, with a port that is free now."""
    how = retyped(argv or [], command, free_port_near(port, host))
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
    sessions that log in as one of its users), or CannotStart saying why (a busy port gives this
    process's ``command`` line, as typed, with a free one)."""
    try:
        return open_session(router_config(port, host, users_file, access, tls))
    except zenoh.ZError as exc:
        reason = port_in_use(port, command, host, sys.argv) if "in use" in str(exc) else zenoh_reason(exc)
        where = " and ".join(f"{'tls' if tls else 'tcp'}/{h}:{port}" for h in listen_hosts(host))
        raise CannotStart(f"cannot listen on {where}: {reason}") from None


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
