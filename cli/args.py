"""Checks of what users type on the command line that Typer's own types cannot express.

Pure (no zenoh, nothing printed): each check returns the value to use or raises BadInput
with the one-line message for the user.
"""

from __future__ import annotations

import ipaddress
import math
import re
from collections.abc import Collection
from pathlib import Path

from turtlectl.runtime.client.errors import BadInput

#: ``--domain``: one key chunk; a number like ROS_DOMAIN_ID is fine
DOMAIN_RE = re.compile(r"^[A-Za-z0-9_\-]+$")


def finite_number(text: str, name: str) -> float:
    """``text`` as a finite float (goto's and teleport's X Y THETA: negative values are fine,
    so they are read as text, not as Typer options)."""
    try:
        value = float(text.replace("_", "?"))  # Python reads 1_0 as 10; a user did not mean that
    except ValueError:
        raise BadInput(f"{name} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise BadInput(f"{name} must be a finite number, got {text!r}")
    return value


def finite_option(value: float | None, option: str) -> float | None:
    """A float option's value if it is finite (Typer's ranges let NaN through: nan < min is False)."""
    if value is not None and not math.isfinite(value):
        raise BadInput(f"{option} must be a finite number, got {value}")
    return value


def domain(text: str) -> str:
    """``--domain``: empty (no domain) or letters, digits, _ and -."""
    if text and not DOMAIN_RE.match(text):
        raise BadInput(f"--domain {text!r}: use letters, digits, _ and - (like lab1 or 42)")
    return text


def node_name(text: str) -> tuple[str, str]:
    """A node's name as ``turtlectl list`` shows it: (its domain, or "", its full name).  A
    ROS-style leading ``/`` is accepted (``/navigator``); ``turtle2/navigator`` is navigator in
    namespace turtle2; ``lab1:navigator`` names navigator in domain lab1.  Names are letters,
    digits, _ and - (as the launch file's), a namespace's joined by ``/``: no wildcards."""
    from turtlectl.cli.system.launchfile import NAME_RE

    domain_part, _, name = text.strip().rpartition(":")
    chunks = name.lstrip("/").split("/")
    if (domain_part and not DOMAIN_RE.match(domain_part)) or not all(NAME_RE.match(c) for c in chunks):
        raise BadInput(
            f"{text!r} is not a node name: letters, digits, _ and -, as the launch file names them "
            "(turtle2/navigator in namespace turtle2; `turtlectl list` shows the running ones)"
        )
    return domain_part, "/".join(chunks)


def node_selector(text: str) -> tuple[str, str]:
    """A node selector (cli.selection: a node's name, a namespace, a turtle, or a glob such as
    ``turtle2/*``) as (its domain, or "", the selector): node_name's rule, with ``*``, ``?`` and
    ``[...]`` allowed in its chunks."""
    domain_part, _, name = text.strip().rpartition(":")
    chunks = name.lstrip("/").split("/")
    if (domain_part and not DOMAIN_RE.match(domain_part)) or not all(SELECTOR_CHUNK.match(c) for c in chunks):
        raise BadInput(
            f"{text!r} is not a node, namespace, turtle or glob: letters, digits, _ and -, with * ? [ ] as "
            "wildcards (turtle2/navigator, turtle2, 'turtle2/*'; `turtlectl list` shows the running nodes)"
        )
    return domain_part, "/".join(chunks)


SELECTOR_CHUNK = re.compile(r"^[A-Za-z0-9_\-*?\[\]!]+$")


def listen_address(text: str) -> str:
    """``--listen``: an IP address to listen on, as an endpoint writes it ([..] around IPv6)."""
    try:
        address = ipaddress.ip_address(text)
    except ValueError:
        raise BadInput(f"--listen {text!r} is not an IP address") from None
    return f"[{address}]" if address.version == 6 else str(address)


def one_format(json: bool, csv: bool) -> None:
    """echo prints JSON lines or CSV, not both."""
    if json and csv:
        raise BadInput("--json and --csv do not go together")


def echo_limit(once: bool, count: int | None) -> int | None:
    """How many messages echo prints before it exits (None: until stopped)."""
    if once and count is not None:
        raise BadInput("--once and --count do not go together")
    return 1 if once else count


def publish_count(once: bool, rate: float | None, times: int | None) -> int | None:
    """How many messages pub sends (None: at ``rate`` until stopped); one by default."""
    if once and (rate is not None or times is not None):
        raise BadInput("--once does not go with --rate or --times")
    return times if times is not None else (None if rate is not None else 1)


#: log levels as ROS 2 spells them, by the name Python's logging gives them
LEVEL_ALIASES = {"WARN": "WARNING", "FATAL": "CRITICAL"}


def level_named(text: str, known: Collection[str], note: str = "") -> str:
    """The log level ``text`` names (any case, ROS's spellings too), one of ``known``; BadInput
    listing ``known`` (and ``note`` after them) when it is none."""
    level = text.strip().upper()
    level = LEVEL_ALIASES.get(level, level)
    if level not in known:
        raise BadInput(f"unknown log level {text!r} (known: {', '.join(known)}{note})")
    return level


def log_level(text: str) -> str:
    """A log level (any case) as the nodes take it: DEBUG, INFO, WARNING (or WARN) or ERROR."""
    from turtlectl.runtime.config import LOG_LEVELS

    return level_named(text, LOG_LEVELS)


def exposure(
    host: str, secure: bool, insecure: bool, joins: bool = False, tls: bool = False, can_secure: bool = True
) -> None:
    """Whether a router may listen on ``host`` (as ``listen_address`` wrote it): beyond loopback
    only with --secure --tls (logins and data encrypted, both ends certified), or when asked with
    --insecure, since anyone who reaches it could then drive the turtle."""
    if secure and joins:
        raise BadInput("--secure runs a router of its own, with its logins: it cannot join one (--connect)")
    if secure and insecure:
        raise BadInput("--secure and --insecure do not go together")
    if tls and not secure:
        raise BadInput("--tls goes with --secure (TLS without logins would let any holder of a certificate drive)")
    if ipaddress.ip_address(host.strip("[]")).is_loopback or insecure or (secure and tls):
        return
    if secure:
        raise BadInput(
            f"--secure --listen {host}: logins would cross the network in clear; add --tls DIR, with the "
            "certificates of `turtlectl certs DIR --host HOST`"
        )
    way = (
        "use --secure --tls DIR (see `turtlectl certs`), or "
        if can_secure
        else "(a secure router is `launch --secure --tls`) "
    )
    raise BadInput(
        f"--listen {host} reaches beyond this machine, and without logins anyone who reaches it can drive the "
        f"turtle, serve a fake navigate_to or reset the robot; {way}add --insecure to run it so on a network you trust"
    )


def tls_folder(path: Path) -> Path:
    """``--tls DIR``: a folder made by ``turtlectl certs`` (BadInput naming what it lacks)."""
    missing = [
        name
        for name in ("ca.pem", "router.pem", "router.key", "client.pem", "client.key")
        if not (path / name).is_file()
    ]
    if missing:
        raise BadInput(f"--tls {path}: no {', '.join(missing)} there (make them with `turtlectl certs {path}`)")
    return path
