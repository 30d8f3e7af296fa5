"""turtlectl: a turtlesim-like robot stack over Eclipse Zenoh, and a platform for your own nodes.

The public API, the only names a user's code needs (typed; ``py.typed``)::

    from turtlectl import Node, run_main          # write a node (docs/tutorials/your-own-node.md)
    from turtlectl import Claim, Interface        # what it alone does, what it may do under --secure
    from turtlectl import Message                 # the base of every message type
    from turtlectl.messages import Twist, Pose    # the message types (docs/interfaces.md)
    from turtlectl import Client                  # a running system from a script (goto, topics, ...)
    from turtlectl import Error                   # what goes wrong; .exit_code is the command line's

``Publisher``, ``Latest``, ``Request``, ``Timer``, ``Declaration``, ``GoalServer`` (its running
goal a ``GoalHandle``) and ``GoalClient`` are what a node's declarations return; ``Future`` what
``Node.call`` returns (``GoalFuture``: a goal's result; ``GoalFailed``: a goal without one), ``Subscription`` what a client's ``subscribe`` returns (each can be
undeclared).  ``Error``'s subclasses: ``BadInput`` (exit 2), ``Unreachable`` (3),
``Failed`` (1; ``GoalCanceled``: a goal canceled, with its result and last feedback), ``Interrupted`` (130), ``CancelUnconfirmed`` (5), ``CannotStart`` (4).
Every error turtlectl raises for its user is one of them (``GoalFailed`` and a ``Future``'s
timeout are ``Failed``; a declaration outside a node's ``Interface`` or a launch target that
names no node class, ``BadInput``; a second node claiming what another holds, ``CannotStart``),
with the exit code the command line ends with in ``exit_code``.  Everything else (``turtlectl.cli``,
``turtlectl.runtime``, ``turtlectl.nodes``, ``turtlectl.sim``) is private: it may change
without notice.

Every module is under ``turtlectl``, so a user's own ``messages.py``, ``nodes/`` or
``runtime.py`` never shadows ours.  How the repository's top-level folders (the design
card's ``messages/``, ``runtime/``, ``sim/``, ``nodes/``, ``cli/``) become this package:
an installed wheel maps them under ``turtlectl/`` (pyproject.toml's ``package-dir``); in the
source tree (``make``'s editable install puts ``src/``, which holds only this package, on
``sys.path``) this package's ``__path__`` also holds the repository root, so
``turtlectl.messages`` is ``messages/`` there, with no import hook, and ``import messages``
finds a user's module, never ours.

The names are loaded when first used, so ``import turtlectl.cli`` (``turtlectl --help``)
pays for none of them.
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if not os.path.isdir(os.path.join(os.path.dirname(__file__), "messages")):  # the source tree: src/turtlectl/
    __path__.append(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

if TYPE_CHECKING:
    from turtlectl.messages.types import Message
    from turtlectl.runtime.client.api import Client
    from turtlectl.runtime.client.errors import (
        BadInput,
        CancelUnconfirmed,
        CannotStart,
        Failed,
        GoalCanceled,
        Interrupted,
        Unreachable,
    )
    from turtlectl.runtime.client.errors import TurtlectlError as Error
    from turtlectl.runtime.client.subscription import Subscription
    from turtlectl.runtime.config import Claim, Interface
    from turtlectl.runtime.entities import Latest, Publisher, Request, Timer
    from turtlectl.runtime.futures import Future
    from turtlectl.runtime.goal_client import GoalClient, GoalFailed, GoalFuture
    from turtlectl.runtime.goals import GoalHandle, GoalServer
    from turtlectl.runtime.handles import Declaration
    from turtlectl.runtime.lifecycle import run_main
    from turtlectl.runtime.node import Node

__all__ = [
    "BadInput",
    "CancelUnconfirmed",
    "CannotStart",
    "Claim",
    "Client",
    "Declaration",
    "Error",
    "Failed",
    "Future",
    "GoalCanceled",
    "GoalClient",
    "GoalFailed",
    "GoalFuture",
    "GoalHandle",
    "GoalServer",
    "Interface",
    "Interrupted",
    "Latest",
    "Message",
    "Node",
    "Publisher",
    "Request",
    "Subscription",
    "Timer",
    "Unreachable",
    "run_main",
]

_HOME = {
    "BadInput": "turtlectl.runtime.client.errors",
    "CancelUnconfirmed": "turtlectl.runtime.client.errors",
    "CannotStart": "turtlectl.runtime.client.errors",
    "Client": "turtlectl.runtime.client.api",
    "Error": "turtlectl.runtime.client.errors",
    "Failed": "turtlectl.runtime.client.errors",
    "GoalCanceled": "turtlectl.runtime.client.errors",
    "Interrupted": "turtlectl.runtime.client.errors",
    "Subscription": "turtlectl.runtime.client.subscription",
    "Unreachable": "turtlectl.runtime.client.errors",
    "Claim": "turtlectl.runtime.config",
    "Declaration": "turtlectl.runtime.handles",
    "Future": "turtlectl.runtime.futures",
    "GoalClient": "turtlectl.runtime.goal_client",
    "GoalFailed": "turtlectl.runtime.goal_client",
    "GoalFuture": "turtlectl.runtime.goal_client",
    "GoalHandle": "turtlectl.runtime.goals",
    "GoalServer": "turtlectl.runtime.goals",
    "Interface": "turtlectl.runtime.config",
    "Latest": "turtlectl.runtime.entities",
    "Message": "turtlectl.messages.types",
    "Node": "turtlectl.runtime.node",
    "Publisher": "turtlectl.runtime.entities",
    "Request": "turtlectl.runtime.entities",
    "Timer": "turtlectl.runtime.entities",
    "run_main": "turtlectl.runtime.lifecycle",
}


def _lazy(module: str, home: dict[str, str], named: dict[str, str] | None = None) -> Callable[[str], Any]:
    """A module's ``__getattr__`` that imports each name of ``home`` (name -> the module that
    defines it, as ``named`` calls it there) when first used: our packages' lazy exports."""

    def __getattr__(name: str) -> Any:
        if name in home:
            return getattr(importlib.import_module(home[name]), (named or {}).get(name, name))
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return __getattr__


__getattr__ = _lazy(__name__, _HOME, {"Error": "TurtlectlError"})


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
