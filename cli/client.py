"""Client sessions of the command-line tools, and checks of what users type for them.

Nothing here prints; functions return data or raise CliError.  Service calls
live in cli.services, topics in cli.topics.
"""

from __future__ import annotations

import contextlib
import re
from collections.abc import Iterator

import zenoh

from cli.errors import CliError, ExitCode
from nodes.session import client_config, close_session, default_domain

OPEN_TIMEOUT = 2.5  # s to reach the router before reporting "nothing to talk to"


ENDPOINT_RE = re.compile(r"^(tcp|udp|tls|quic|ws)/(\[[0-9A-Fa-f:.]+\]|[^\s/:\[\]]+):(\d{1,5})$")


def check_endpoint(connect: str) -> str:
    """``connect`` if it is a Zenoh endpoint (``tcp/HOST:PORT``), else CliError(BAD_INPUT)."""
    match = ENDPOINT_RE.match(connect)
    if not match or not 0 < int(match.group(3)) <= 65535:
        raise CliError(
            ExitCode.BAD_INPUT,
            f"{connect!r} is not an endpoint: write it as tcp/HOST:PORT (from --connect or TURTLECTL_CONNECT)",
        )
    return connect


def check_key(text: str, publish: bool = False) -> str:
    """A topic as typed by a user as a Zenoh key expression: a ROS-style leading '/' is
    dropped; anything Zenoh would refuse is CliError(BAD_INPUT).  With ``publish``, one
    plain key: no wildcards, nothing of turtlectl's own ``@`` space."""
    key = text[1:] if text.startswith("/") and len(text) > 1 else text
    try:
        key = str(zenoh.KeyExpr(key))
    except zenoh.ZError:
        raise CliError(
            ExitCode.BAD_INPUT, f"{text!r} is not a valid key expression (like robot/status or turtle1/*)"
        ) from None
    if publish and ("*" in key or "$" in key or key.startswith("@")):
        raise CliError(ExitCode.BAD_INPUT, f"{text!r}: publish on one plain key, without wildcards or '@'")
    return key


@contextlib.contextmanager
def client_session(connect: str) -> Iterator[zenoh.Session]:
    """A Zenoh client session to the router at ``connect``, closed (bounded) on exit."""
    check_endpoint(connect)
    try:
        session = zenoh.open(client_config(connect, OPEN_TIMEOUT, default_domain()))
    except zenoh.ZError:
        raise CliError(
            ExitCode.UNREACHABLE, f"no turtlectl system at {connect} (is `turtlectl launch` running?)"
        ) from None
    try:
        yield session
    finally:
        close_session(session)
