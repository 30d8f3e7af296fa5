"""Where a turtlectl system is reached, without importing zenoh (pure): the default router
endpoint and the environment variables that choose the endpoint and the domain."""

from __future__ import annotations

import os

DEFAULT_PORT = 7447
DEFAULT_ENDPOINT = f"tcp/127.0.0.1:{DEFAULT_PORT}"
CONNECT_ENV = "TURTLECTL_CONNECT"
DOMAIN_ENV = "TURTLECTL_DOMAIN"
LOG_DIR_ENV = "TURTLECTL_LOG_DIR"  # the parent folder of run folders, as `launch --log-dir` names it


def default_domain() -> str:
    """The domain the environment chooses (``TURTLECTL_DOMAIN``), '' for none."""
    return os.environ.get(DOMAIN_ENV, "")


TLS_ENV = "TURTLECTL_TLS"  # the folder of `turtlectl certs` (ca.pem, client.pem, client.key) for tls/ endpoints


def tls_folder() -> str:
    """The folder with the CA and client certificate for ``tls/`` endpoints ('' if not set)."""
    return os.environ.get(TLS_ENV, "")


PEER_TIMEOUT_ENV = "TURTLECTL_PEER_TIMEOUT"
#: s: a peer (router, node or tool) heard nothing from for this long is taken for gone and its link
#: closed; nothing bound for it waits longer than this either.  See peer_timeout.
DEFAULT_PEER_TIMEOUT = 3.0
PEER_TIMEOUT_RANGE = (0.5, 60.0)  # s: the values TURTLECTL_PEER_TIMEOUT may take
#: s: the longest a message that may not be dropped (a declaration, a query's reply) waits for room
#: in a link's queue before that link is closed.  While it waits, Zenoh's routing and that link's
#: droppable messages wait with it (eclipse-zenoh/zenoh#1876, #2584), so a slow link's full queue
#: stalls every stream of the process for this long; a link to a live peer on this host never
#: stays full this long, one over a lossy radio may.  At most the peer timeout.
BLOCKED_LINK_WAIT = 0.5


def peer_timeout() -> float:
    """The bound, in s, within which a silent peer is detected (``TURTLECTL_PEER_TIMEOUT``, default
    ``DEFAULT_PEER_TIMEOUT``): every session's link lease, and how long opening or accepting a
    link may take (a message that may not be dropped waits at most ``BLOCKED_LINK_WAIT`` of it for
    room in a link's queue before that link is closed).  A value that is no
    number or lies outside ``PEER_TIMEOUT_RANGE`` gives ValueError, naming the variable."""
    text = os.environ.get(PEER_TIMEOUT_ENV, "")
    if not text:
        return DEFAULT_PEER_TIMEOUT
    low, high = PEER_TIMEOUT_RANGE
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not low <= value <= high:
        raise ValueError(f"{PEER_TIMEOUT_ENV}={text!r}: give seconds from {low:g} to {high:g}")
    return value
