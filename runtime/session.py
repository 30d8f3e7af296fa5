"""Opening and closing Zenoh sessions the one way turtlectl does it.

* The supervisor runs a router on ``tcp/127.0.0.1:PORT``; multicast scouting
  is off everywhere, so only processes told the endpoint can join.
* Nodes are peers: they find each other through the router (gossip) and then
  talk directly, one hop less (rmw_zenoh's pattern).
* Command-line clients are Zenoh clients of the router.
* Closing is bounded: zenoh-python can hang at exit when a session with
  callback subscribers is not closed, so we close explicitly, in a thread,
  and give up after a deadline.
"""

from __future__ import annotations

import json
import os
import socket
import threading
from typing import Any

import zenoh

from turtlectl.runtime.config import Credentials
from turtlectl.runtime.endpoint import BLOCKED_LINK_WAIT, peer_timeout, tls_folder
from turtlectl.runtime.sockets import Unlinger


def _base(mode: str, domain: str = "") -> zenoh.Config:
    conf = zenoh.Config()
    conf.insert_json5("mode", json.dumps(mode))
    conf.insert_json5("scouting/multicast/enabled", "false")
    # open returns at once instead of waiting up to 500 ms for scouting (zenoh 1.10 waited the whole
    # delay in a router, and in about half of the peer opens here, multicast off or not); declarations
    # made before the router is reached are sent when it is
    conf.insert_json5("scouting/delay", "0")
    # a peer heard nothing from for `bound` s is gone: its link's lease ends then (keep-alives every
    # bound/4), and opening or accepting a link gives up as soon; a message that may not be dropped
    # waits at most BLOCKED_LINK_WAIT for room toward a peer, since the whole process's routing waits
    # with it (Zenoh's defaults: 10 s, 10 s, 10 s, 5 s)
    bound = peer_timeout()
    conf.insert_json5("transport/link/tx/lease", str(int(bound * 1000)))
    blocked = min(bound, BLOCKED_LINK_WAIT)
    conf.insert_json5("transport/link/tx/queue/congestion_control/block/wait_before_close", str(int(blocked * 1e6)))
    conf.insert_json5("transport/unicast/open_timeout", str(int(bound * 1000)))
    conf.insert_json5("transport/unicast/accept_timeout", str(int(bound * 1000)))
    if domain:  # every key this session uses is put under "<domain>/": systems on one router never mix
        conf.insert_json5("namespace", json.dumps(domain))
    return conf


def listen_hosts(host: str) -> list[str]:
    """The addresses a router told to listen on ``host`` listens on: ``host``, and loopback too
    when ``host`` is one network address (its own machine's tools and nodes keep reaching it
    at 127.0.0.1 without being told the network address); ``0.0.0.0``/``[::]`` include loopback."""
    if host in ("0.0.0.0", "[::]") or host.startswith("127.") or host in ("[::1]", "localhost"):
        return [host]
    return [host, "[::1]" if host.startswith("[") else "127.0.0.1"]


def router_config(
    port: int,
    host: str = "127.0.0.1",
    users_file: str | None = None,
    access: dict[str, Any] | None = None,
    tls: str | None = None,
) -> zenoh.Config:
    """A router listening on ``host`` (loopback unless told otherwise; ``listen_hosts``) at ``port``; with
    ``users_file`` (``user:password`` lines) it accepts only sessions that log in as one of
    them, and with ``access`` (Zenoh's ``access_control`` section) lets each do only that; with
    ``tls`` (the folder of ``turtlectl certs``) it listens on ``tls/`` with mutual TLS."""
    conf = _base("router")
    scheme = "tls" if tls else "tcp"
    conf.insert_json5("listen/endpoints", json.dumps([f"{scheme}/{h}:{port}" for h in listen_hosts(host)]))
    if tls:  # mutual TLS: only sessions whose certificate the CA signed
        conf.insert_json5(
            "transport/link/tls",
            json.dumps(
                {
                    "root_ca_certificate": os.path.join(tls, "ca.pem"),
                    "listen_private_key": os.path.join(tls, "router.key"),
                    "listen_certificate": os.path.join(tls, "router.pem"),
                    "enable_mtls": True,
                }
            ),
        )
    if users_file is not None:
        conf.insert_json5("transport/auth/usrpwd", json.dumps({"dictionary_file": users_file}))
    if access is not None:
        conf.insert_json5("access_control", json.dumps(access))
    return conf


def _tls(conf: zenoh.Config, connect: str) -> zenoh.Config:
    """For a ``tls/`` endpoint: trust the CA of ``$TURTLECTL_TLS`` and show its client
    certificate (mutual TLS)."""
    folder = tls_folder()
    if connect.startswith("tls/") and folder:
        conf.insert_json5(
            "transport/link/tls",
            json.dumps(
                {
                    "root_ca_certificate": os.path.join(folder, "ca.pem"),
                    "enable_mtls": True,
                    "connect_private_key": os.path.join(folder, "client.key"),
                    "connect_certificate": os.path.join(folder, "client.pem"),
                }
            ),
        )
    return conf


def _log_in(conf: zenoh.Config, credentials: Credentials | None) -> zenoh.Config:
    if credentials is not None:
        conf.insert_json5(
            "transport/auth/usrpwd", json.dumps({"user": credentials.user, "password": credentials.password})
        )
    return conf


def node_session_config(connect: str, domain: str = "", credentials: Credentials | None = None) -> zenoh.Config:
    """A node's session: a peer (``peer_config``), or with ``credentials`` (a --secure system) a
    client of the router, logged in: no other process can reach it but through the router."""
    if credentials is None:
        return peer_config(connect, domain)
    conf = _base("client", domain)
    conf.insert_json5("connect/endpoints", json.dumps([connect]))
    return _log_in(_tls(conf, connect), credentials)


def local_address_towards(endpoint: str) -> str:
    """This machine's address on the route to ``endpoint`` (``tcp/HOST:PORT``), written for an
    endpoint: 127.0.0.1 for a router on loopback.  Asks the kernel's routing table (a UDP
    socket's connect sends nothing); falls back to 127.0.0.1."""
    _, _, address = endpoint.partition("/")
    host, _, port = address.rpartition(":")
    host = host.strip("[]")
    try:
        infos = socket.getaddrinfo(host, int(port), type=socket.SOCK_DGRAM)
        family, _, _, _, target = infos[0]
        with socket.socket(family, socket.SOCK_DGRAM) as probe:
            probe.connect(target)
            local = probe.getsockname()[0]
    except (OSError, ValueError, IndexError):
        return "127.0.0.1"
    return f"[{local}]" if ":" in local else local


def peer_config(connect: str, domain: str = "") -> zenoh.Config:
    """A node: a peer that joins through the router at ``connect`` and listens, for the other
    peers, on the address it reaches the router from (loopback when the router is local)."""
    conf = _base("peer", domain)
    conf.insert_json5("connect/endpoints", json.dumps([connect]))
    conf.insert_json5("listen/endpoints", json.dumps([f"tcp/{local_address_towards(connect)}:0"]))
    return conf


def client_config(
    connect: str, timeout: float, domain: str = "", credentials: Credentials | None = None
) -> zenoh.Config:
    """A command-line client of the router at ``connect``, logged in with ``credentials`` if
    given; opening fails after ``timeout`` s."""
    conf = _base("client", domain)
    conf.insert_json5("connect/endpoints", json.dumps([connect]))
    conf.insert_json5("connect/timeout_ms", str(int(timeout * 1000)))
    conf.insert_json5("connect/exit_on_failure", "true")
    return _log_in(_tls(conf, connect), credentials)


def open_session(conf: zenoh.Config) -> zenoh.Session:
    """``zenoh.open(conf)``, the one way every turtlectl process opens a session: its links toward
    a peer that goes silent then close without stalling the process (runtime.sockets)."""
    session = zenoh.open(conf)
    Unlinger.ensure()
    return session


def close_session(session: zenoh.Session, timeout: float = 2.0) -> bool:
    """Close ``session``, waiting at most ``timeout`` s; True if it closed in time."""
    closer = threading.Thread(target=session.close, name="zenoh-close", daemon=True)
    closer.start()
    closer.join(timeout)
    return not closer.is_alive()


def zenoh_reason(exc: Exception) -> str:
    """Zenoh's error without the Rust source locations it appends (`` at /root/.cargo/...``)."""
    text = str(exc)
    cut = text.find(" at /")
    return (text[:cut] if cut > 0 else text).strip(" [].")
