"""What a node's declarations return: a handle that can be undeclared.

``Node.subscribe``, ``serve``, ``answer_json`` and ``watch_liveliness`` return a
``Declaration``; ``publisher``, ``latest`` and ``timer`` return their own objects, each with
the same ``undeclare()``.  Undeclaring withdraws the Zenoh entity and the node's graph token
for it (``turtlectl list`` stops showing it), and no callback of it runs on the node thread
afterwards, not even one already queued.  Undeclaring twice does nothing; what is still
declared when the node stops goes with its session.

Pure bookkeeping: the Zenoh entities come in from the node (anything with ``undeclare()``).
"""

from __future__ import annotations

from typing import Protocol


class Undeclarable(Protocol):
    def undeclare(self) -> None: ...


class Declaration:
    """One declaration of a node and what it is made of (its Zenoh entity, its graph token).
    ``active`` is False once undeclared."""

    def __init__(self, owner: list[Declaration], what: str, key: str):
        self.what = what  # "subscription", "service", ...
        self.key = key
        self.active = True
        self._parts: list[Undeclarable] = []
        self._owner = owner
        owner.append(self)

    def add(self, part: Undeclarable | None) -> None:
        """One more entity that makes this declaration (None: nothing to add)."""
        if part is not None:
            self._parts.append(part)

    def undeclare(self) -> None:
        """Withdraw it: its entities undeclared, its callbacks silenced.  Idempotent."""
        if not self.active:
            return
        self.active = False
        if self in self._owner:
            self._owner.remove(self)
        parts, self._parts = self._parts, []
        for part in parts:
            part.undeclare()

    def __repr__(self) -> str:
        return f"<{self.what} on {self.key}{'' if self.active else ' (undeclared)'}>"
