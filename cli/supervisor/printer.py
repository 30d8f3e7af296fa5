"""Prefixed, line-buffered output for the supervisor and its children (thread-safe)."""

from __future__ import annotations

import sys
import threading
from typing import TextIO

_COLOURS = (36, 33, 32, 35, 34, 31, 96, 93, 92, 95)


class Printer:
    """Writes ``name | line`` to ``stream``; names are padded and, on a terminal, coloured."""

    def __init__(self, names: list[str], stream: TextIO | None = None, colour: bool | None = None):
        self.stream = stream or sys.stdout
        self.colour = self.stream.isatty() if colour is None else colour
        self.width = max([len(n) for n in names] + [len("launch")])
        self._colours = {name: _COLOURS[i % len(_COLOURS)] for i, name in enumerate(names)}
        self._lock = threading.Lock()

    def line(self, name: str, text: str) -> None:
        label = name.ljust(self.width)
        if self.colour:
            code = self._colours.get(name, 1)
            label = f"\033[{code}m{label}\033[0m"
        with self._lock:
            self.stream.write(f"{label} | {text.rstrip()}\n")
            self.stream.flush()

    def system(self, text: str) -> None:
        """A line from the supervisor itself."""
        self.line("launch", text)
