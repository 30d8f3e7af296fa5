"""Ctrl-C around a command's result: once it is out, or while Zenoh closes, a Ctrl-C changes
nothing (no exit code 130, no traceback from Zenoh's threads while the process ends)."""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from collections.abc import Iterator


def ignore_sigint() -> None:
    """From now on Ctrl-C changes nothing (main thread only): the result is out, or Zenoh is closing.

    SIG_IGN, so that it also holds while the interpreter shuts down (Python handlers are reset
    then).  A Ctrl-C already on its way when it is set either raises KeyboardInterrupt here
    (set it again) or is reported by Python as "Signal 2 ignored due to race condition"
    (cli.main's unraisable hook keeps that quiet)."""
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except KeyboardInterrupt:
        signal.signal(signal.SIGINT, signal.SIG_IGN)


def quiet_unraisable(info: sys.UnraisableHookArgs) -> None:
    """sys.unraisablehook: drop Python's report of a Ctrl-C that arrived as it was being ignored."""
    if isinstance(info.exc_value, OSError) and "ignored due to race condition" in str(info.exc_value):
        return
    sys.__unraisablehook__(info)


@contextlib.contextmanager
def sigint_deferred() -> Iterator[None]:
    """Ignore Ctrl-C while the block runs (on the main thread; elsewhere nothing changes)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGINT)
    ignore_sigint()
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@contextlib.contextmanager
def stop_on_signals(also: tuple[signal.Signals, ...] = ()) -> Iterator[threading.Event]:
    """An event set by Ctrl-C or SIGTERM (and the signals in ``also``) while the block runs (a
    long command's way to end cleanly: record, play, foxglove, teleop); the previous handlers
    come back after it."""
    stop = threading.Event()
    sigs = (signal.SIGINT, signal.SIGTERM, *also)
    previous = {sig: signal.signal(sig, lambda *_: stop.set()) for sig in sigs}
    try:
        yield stop
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
