"""Run folders of ``turtlectl launch``: one per run, ``<parent>/<date>-<time>-<pid>``, the
oldest removed so that only the newest ``keep_logs`` remain (no zenoh here)."""

from __future__ import annotations

import os
import re
import shutil
import time
from collections.abc import Callable
from pathlib import Path

#: the name of a run folder: local date and time, then the supervisor's pid
RUN_RE = re.compile(r"^(?P<stamp>\d{4}-\d{2}-\d{2}-\d{2}-\d{2}-\d{2})-(?P<pid>\d+)$")


def default_parent() -> Path:
    return Path.home() / ".turtlectl" / "log"


def run_folder(parent: Path, now: float | None = None, pid: int | None = None) -> Path:
    """This run's folder under ``parent`` (not created)."""
    stamp = time.strftime("%Y-%m-%d-%H-%M-%S", time.localtime(time.time() if now is None else now))
    return parent / f"{stamp}-{os.getpid() if pid is None else pid}"


def pid_running(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # someone else's process
        return True
    return True


def prune(parent: Path, keep: int, current: Path, running: Callable[[int], bool] = pid_running) -> list[Path]:
    """Remove the run folders under ``parent`` beyond the newest ``keep``, ``current`` counted
    first; never one whose launch is still running (its pid is alive), nor anything that is
    not named like a run folder.  ``keep`` 0 keeps them all.  Returns what was removed."""
    if keep <= 0:
        return []
    runs = []
    for path in parent.iterdir():
        match = RUN_RE.match(path.name)
        if match and path != current and path.is_dir() and not path.is_symlink():
            runs.append((match["stamp"], int(match["pid"]), path))
    runs.sort(reverse=True)  # newest first
    removed = []
    for _, pid, path in runs[max(keep - 1, 0) :]:
        if pid != os.getpid() and running(pid):
            continue  # another launch still writing there
        shutil.rmtree(path, ignore_errors=True)
        removed.append(path)
    return removed
