"""Prefixed, line-buffered output for the supervisor and its children (thread-safe),
also written to one log file per node in a run folder."""

from __future__ import annotations

import sys
import threading
import time
from pathlib import Path
from typing import TextIO

from turtlectl.messages.keys import name_chunk

_COLOURS = (36, 33, 32, 35, 34, 31, 96, 93, 92, 95)
SYSTEM = "launch"


class Printer:
    """Writes ``name | line`` to ``stream`` (names padded and, on a terminal, coloured) and,
    once ``log_to`` is called, each line with its local time (ms) to ``<folder>/<name>.log``."""

    def __init__(self, names: list[str], stream: TextIO | None = None, colour: bool | None = None):
        self.stream = stream or sys.stdout
        self.colour = self.stream.isatty() if colour is None else colour
        self.width = max([len(n) for n in names] + [len(SYSTEM)])
        self._colours = {name: _COLOURS[i % len(_COLOURS)] for i, name in enumerate(names)}
        self._lock = threading.Lock()
        self._logs: dict[str, TextIO] = {}
        self.folder: Path | None = None

    def log_to(self, folder: Path, names: list[str]) -> None:
        """Open ``folder/<name>.log`` for every node and the supervisor (``launch.log``)."""
        folder.mkdir(parents=True, exist_ok=True)
        self.folder = folder
        for name in [SYSTEM, *names]:
            self._logs[name] = open(folder / f"{name_chunk(name)}.log", "a", encoding="utf-8", buffering=1)  # noqa: SIM115

    def log_path(self, name: str) -> Path | None:
        """Where node ``name``'s lines are kept (None: no log files)."""
        return None if self.folder is None else self.folder / f"{name_chunk(name)}.log"

    def line(self, name: str, text: str, terminal: bool = True) -> None:
        """``terminal`` False: into the log file only (a node's output that was shown once already)."""
        text = text.rstrip()
        label = name.ljust(self.width)
        if self.colour:
            code = self._colours.get(name, 1)
            label = f"\033[{code}m{label}\033[0m"
        with self._lock:
            try:
                if terminal:
                    self.stream.write(f"{label} | {text}\n")
                    self.stream.flush()
            except (BrokenPipeError, ValueError):  # our reader went away: keep the log files going
                pass
            log = self._logs.get(name)
            if log is not None:
                now = time.time()
                stamp = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(now)) + f".{int(now % 1 * 1000):03d}"
                log.write(f"{stamp} {text}\n")

    def system(self, text: str) -> None:
        """A line from the supervisor itself."""
        self.line(SYSTEM, text)

    def close(self) -> None:
        with self._lock:
            for log in self._logs.values():
                log.close()
            self._logs.clear()
