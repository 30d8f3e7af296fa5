"""Closing a link toward a silent peer without stalling the process (no zenoh here).

Zenoh's TCP and TLS links set ``SO_LINGER`` to 10 s on every socket, fixed when Zenoh is
compiled.  When a peer stops answering (its host cut off, its Wi-Fi gone), the socket's send
buffer toward it fills; once the link's lease ends Zenoh closes it, and ``close()`` of a lingering
socket with unsent data blocks its thread until the data is acknowledged or the linger time is up:
10 s, during which Zenoh's routing in this process waits too, so this process's traffic with every
other peer stops as well.  Without ``SO_LINGER`` a close returns at once and the kernel drops the
connection in the background, which is what a robot that lost one peer needs.

Sockets are made inside Zenoh, so no call hands them to us: ``Unlinger`` looks at the process's
open sockets (``/proc/self/fd``) every ``period`` s and turns ``SO_LINGER`` off on each new TCP
socket, through a duplicate of its descriptor (socket options belong to the socket, not the
descriptor).  A link lives for seconds to days and a lease is seconds, so a sweep a second is soon
enough; one sweep of a node's few dozen descriptors costs well under a millisecond.  On a system
without ``/proc`` it does nothing.
"""

from __future__ import annotations

import os
import socket
import struct
import threading

PERIOD = 0.5  # s between two looks at the process's sockets
_FDS = "/proc/self/fd"
_NO_LINGER = struct.pack("ii", 0, 0)


def unlinger_new_sockets(seen: set[str]) -> int:
    """Turn ``SO_LINGER`` off on every TCP socket of this process not in ``seen`` (socket inodes,
    updated); returns how many had it on."""
    try:
        names = os.listdir(_FDS)
    except OSError:
        return 0
    changed = 0
    current: set[str] = set()
    for name in names:
        try:
            target = os.readlink(f"{_FDS}/{name}")
        except OSError:
            continue
        if not target.startswith("socket:["):
            continue
        current.add(target)
        if target in seen:
            continue
        try:
            dup = socket.socket(fileno=os.dup(int(name)))
        except (OSError, ValueError):
            continue
        try:
            if dup.type == socket.SOCK_STREAM and dup.family in (socket.AF_INET, socket.AF_INET6):
                onoff, _ = struct.unpack("ii", dup.getsockopt(socket.SOL_SOCKET, socket.SO_LINGER, 8))
                if onoff:
                    dup.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, _NO_LINGER)
                    changed += 1
        except OSError:
            pass
        finally:
            dup.close()  # the duplicate only: the socket stays open under Zenoh's descriptor
    seen.clear()
    seen.update(current)  # the sockets closed since are forgotten: the set stays as small as the process
    return changed


class Unlinger:
    """The process's sweeper: one daemon thread, started by ``ensure`` (idempotent)."""

    _lock = threading.Lock()
    _thread: threading.Thread | None = None

    @classmethod
    def ensure(cls, period: float = PERIOD) -> None:
        with cls._lock:
            if cls._thread is not None and cls._thread.is_alive():
                return
            if not os.path.isdir(_FDS):
                return
            seen: set[str] = set()
            unlinger_new_sockets(seen)
            cls._thread = threading.Thread(target=cls._run, args=(seen, period), name="unlinger", daemon=True)
            cls._thread.start()

    @staticmethod
    def _run(seen: set[str], period: float) -> None:
        stop = threading.Event()
        while not stop.wait(period):
            unlinger_new_sockets(seen)
