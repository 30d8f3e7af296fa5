"""A node declares only what its interface names: what it publishes, subscribes to, serves,
calls and watches (``runtime.config.Interface``, handed over in the node's config: its kind's,
or what an undeclared user kind may do).  Under ``launch --secure`` the router allows exactly
that and drops anything else silently; the runtime refuses it at once, in every mode, so a
mismatch fails a test or the node's start instead of quietly breaking a secure system."""

from __future__ import annotations

import os
import traceback

import zenoh

from turtlectl.runtime.client.errors import BadInput
from turtlectl.runtime.config import Interface

#: a declaration's verb -> the Interface field that names its keys
FIELDS = {"publish": "publishes", "subscribe": "subscribes", "serve": "serves", "call": "calls", "watch": "watches"}

_RUNTIME = os.path.dirname(os.path.abspath(__file__))


class OutsideInterface(BadInput):
    """Node ``node`` declared something its interface does not name: ``verb`` on ``key``, where
    it may only on ``allowed`` (a defect of the node's code or its declaration: starting it
    again cannot help; exit code 2, as a node process ends then)."""

    def __init__(self, node: str, verb: str, key: str, allowed: tuple[str, ...]):
        named = ", ".join(allowed) if allowed else "nothing"
        super().__init__(
            f"{node} may not {verb} {key}: its Interface {FIELDS[verb]} {named} "
            f"(add {key} to {FIELDS[verb]} in the node class's Interface)"
        )
        self.node, self.verb, self.key, self.allowed = node, verb, key, allowed


def check(node: str, interface: Interface | None, verb: str, key: str) -> None:
    """Raise OutsideInterface unless ``interface`` (None: no check) lets ``node`` ``verb`` ``key``
    (a key expression: it must lie inside one the interface names)."""
    if interface is None:
        return
    allowed: tuple[str, ...] = getattr(interface, FIELDS[verb])
    wanted = zenoh.KeyExpr(key)
    if any(zenoh.KeyExpr(k).includes(wanted) for k in allowed):
        return
    raise OutsideInterface(node, verb, key, allowed)


def where(exc: BaseException) -> str:
    """``file:line`` of the node's own code that made the declaration (the last frame outside
    the runtime), or ''."""
    frames = [f for f in traceback.extract_tb(exc.__traceback__) if not f.filename.startswith(_RUNTIME)]
    return f"{frames[-1].filename}:{frames[-1].lineno}" if frames else ""
