"""Checks of what a user gives a client: an endpoint, a turtle's name.

Pure (no zenoh, nothing printed): each check returns the value to use or raises BadInput
with the one-line message for the user.
"""

from __future__ import annotations

import re

from turtlectl.runtime.client.errors import BadInput

#: ``--connect``: a Zenoh endpoint, ``PROTOCOL/HOST:PORT`` ([..] around an IPv6 address)
ENDPOINT_RE = re.compile(r"^(tcp|udp|tls|quic|ws)/(\[[0-9A-Fa-f:.]+\]|[^\s/:\[\]]+):(\d{1,5})$")
#: a turtle's name: one key chunk, as the simulator spawns it
TURTLE_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_\-]{0,62}$")


def turtle_name(text: str) -> str:
    """``--turtle``: a turtle's name, checked ("": none given).  The namespace its nodes run in
    is the running system's to say (runtime.client.session.live_turtle_namespace)."""
    text = text.strip().strip("/")
    if text and not TURTLE_NAME.match(text):
        raise BadInput(f"--turtle {text!r}: a turtle's name, letters, digits, _ and - (like turtle2)")
    return text


def endpoint(connect: str) -> str:
    """``connect`` if it is a Zenoh endpoint (``tcp/HOST:PORT``)."""
    match = ENDPOINT_RE.match(connect)
    if not match or not 0 < int(match.group(3)) <= 65535:
        raise BadInput(
            f"{connect!r} is not an endpoint: write it as tcp/HOST:PORT (from --connect or TURTLECTL_CONNECT)"
        )
    return connect
