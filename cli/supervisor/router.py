"""``turtlectl router``: a Zenoh router alone, for systems whose nodes join with ``launch --connect``
(on other hosts, or to survive a router restart), as rmw_zenoh's ``rmw_zenohd``."""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable

import zenoh

from cli.errors import CliError, ExitCode
from cli.supervisor.manager import port_in_use
from runtime.session import close_session, router_config, zenoh_reason


def run_router(port: int, host: str, on_ready: Callable[[], None]) -> None:
    """Serve as a router on tcp/``host``:``port`` until SIGINT/SIGTERM; ``on_ready()`` once listening."""
    stop = threading.Event()
    try:
        session = zenoh.open(router_config(port, host))
    except zenoh.ZError as exc:
        reason = port_in_use(port, "router", host) if "in use" in str(exc) else zenoh_reason(exc)
        raise CliError(ExitCode.CANNOT_START, f"cannot listen on tcp/{host}:{port}: {reason}") from None
    previous = {sig: signal.signal(sig, lambda *_: stop.set()) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        on_ready()
        while not stop.wait(0.2):
            pass
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        close_session(session)
