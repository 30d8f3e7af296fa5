"""Which nodes a selector names (pure: no zenoh): the one rule behind ``launch --only`` and
``--exclude``, ``log --node``, ``log-level`` and ``param``'s NODE.

A selector is, with a ROS-style leading ``/`` dropped:

- a node's full name (``turtle2/navigator``, ``sim``);
- a glob over full names (``turtle2/*``, ``*/navigator``, ``*``: fnmatch's ``*``, ``?``, ``[...]``);
- a namespace, naming every node in it (``turtle2``: ``turtle2/navigator``, ``turtle2/status_monitor``...);
- a turtle, naming every node that drives it: the nodes of its namespace, and for turtle1 the
  nodes outside any namespace too (turtle1's in the seed's launch file: ``navigate_to``,
  ``robot/status``), but never the simulator, which drives every turtle (kind ``sim``).

``kinds`` maps each node's full name to its kind (the launch file's ``run``) where the caller
knows it; a node of unknown kind outside any namespace is taken to drive turtle1 unless it is
named as the simulator's kind (``sim``).
"""

from __future__ import annotations

import fnmatch
from collections.abc import Iterable, Mapping

from turtlectl.messages.keys import namespace_of, turtle_of

#: the kind of the node that drives every turtle (no turtle's own)
SIMULATOR = "sim"
_GLOB = frozenset("*?[")


def is_glob(selector: str) -> bool:
    """Whether ``selector`` is a glob (``*``, ``?`` or ``[``)."""
    return not _GLOB.isdisjoint(selector)


def selects(selector: str, name: str, kind: str | None = None) -> bool:
    """Whether ``selector`` names node ``name`` (its full name; ``kind``: its kind, None: unknown)."""
    wanted = selector.strip().lstrip("/").rstrip("/")
    if not wanted:
        return False
    if name == wanted or fnmatch.fnmatchcase(name, wanted) or name.startswith(f"{wanted}/"):
        return True
    if "/" in wanted or is_glob(wanted):
        return False
    simulator = (kind if kind is not None else name) == SIMULATOR
    return not simulator and turtle_of(namespace_of(name)) == wanted


def selected(selectors: Iterable[str], names: Iterable[str], kinds: Mapping[str, str] | None = None) -> list[str]:
    """The nodes of ``names`` (in their order) that any of ``selectors`` names."""
    chosen = list(selectors)
    known = kinds or {}
    return [n for n in names if any(selects(s, n, known.get(n)) for s in chosen)]


def unmatched(selectors: Iterable[str], names: Iterable[str], kinds: Mapping[str, str] | None = None) -> list[str]:
    """The selectors of ``selectors`` that name none of ``names``."""
    listed = list(names)
    known = kinds or {}
    return [s for s in selectors if not any(selects(s, n, known.get(n)) for n in listed)]
