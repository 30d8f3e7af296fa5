"""Two hosts joined by a cable whose faults a test sets: loss, latency, down, flapping.

Two network namespaces stand for two machines.  The cable between them is this process: a TUN
device in each namespace (made here from ``/dev/net/tun`` in the root namespace, then moved
into its namespace with ``ip link set DEV netns NS``; the open file descriptor stays the
device's), and a thread that reads each IP packet from one device and writes it to the other,
dropping it with the loss probability, holding it for the added latency (a delay queue), or
dropping every packet while the cable is down.  The faults are therefore real packet-level
loss and latency under real TCP (retransmissions, congestion windows, timeouts), as a Wi-Fi
link fading would give.

Why not ``tc qdisc ... netem``: not every kernel has the netem scheduler (this project's CI
kernel is built without ``CONFIG_NET_SCH_NETEM``: "Specified qdisc kind is unknown"), and
neither ``iptables`` nor ``nft`` is installed there; a TUN device needs only the kernel's
``tun`` driver, ``ip`` and root.  Standard library only: shared by the tests and
``bench/fleet_hosts.py``.
"""

from __future__ import annotations

import fcntl
import heapq
import os
import random
import secrets
import select
import struct
import subprocess
import threading
import time

TUNSETIFF = 0x400454CA
IFF_TUN = 0x0001
IFF_NO_PI = 0x1000
MTU = 1500


class NoNetwork(Exception):
    """Network namespaces or TUN devices cannot be made here (not root, no ``ip``, no tun)."""


def _ip(*argv: str) -> None:
    try:
        done = subprocess.run(["ip", *argv], capture_output=True, text=True, timeout=20)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise NoNetwork(f"ip {' '.join(argv)}: {exc}") from None
    if done.returncode != 0:
        raise NoNetwork(f"ip {' '.join(argv)}: {done.stderr.strip()}")


def _tun(name: str) -> int:
    try:
        fd = os.open("/dev/net/tun", os.O_RDWR | os.O_NONBLOCK)
    except OSError as exc:
        raise NoNetwork(f"/dev/net/tun: {exc}") from None
    try:
        fcntl.ioctl(fd, TUNSETIFF, struct.pack("16sH", name.encode(), IFF_TUN | IFF_NO_PI))
    except OSError as exc:
        os.close(fd)
        raise NoNetwork(f"TUNSETIFF {name}: {exc}") from None
    return fd


class Wire:
    """Namespaces ``a`` and ``b`` (named ``{prefix}-a-TAG``, ``{prefix}-b-TAG``) with addresses
    ``a_addr`` and ``b_addr``, joined by this cable.  Faults, settable at any time, apply to both
    directions: ``loss`` (probability a packet is dropped), ``latency`` (s added to each packet),
    ``down`` (every packet dropped).  Use as a context manager: the namespaces and devices go
    when it ends."""

    def __init__(self, prefix: str = "tw", a_addr: str = "10.231.8.1", b_addr: str = "10.231.8.2"):
        tag = secrets.token_hex(3)
        self.a, self.b = f"{prefix}-a-{tag}", f"{prefix}-b-{tag}"
        self.a_addr, self.b_addr = a_addr, b_addr
        self.loss = 0.0
        self.latency = 0.0
        self.down = False
        self.forwarded = 0
        self.dropped = 0
        self._random = random.Random(0x7E1)
        self._fds: list[int] = []
        self._made: list[str] = []
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._tag = tag

    def __enter__(self) -> Wire:
        try:
            for ns in (self.a, self.b):
                _ip("netns", "add", ns)
                self._made.append(ns)
            for ns, dev, mine, theirs in (
                (self.a, f"wa{self._tag}", self.a_addr, self.b_addr),
                (self.b, f"wb{self._tag}", self.b_addr, self.a_addr),
            ):
                self._fds.append(_tun(dev))
                _ip("link", "set", dev, "netns", ns)
                _ip("-n", ns, "addr", "add", mine, "peer", f"{theirs}/32", "dev", dev)
                _ip("-n", ns, "link", "set", dev, "mtu", str(MTU), "up")
                _ip("-n", ns, "link", "set", "lo", "up")
        except BaseException:
            self.close()
            raise
        self._thread = threading.Thread(target=self._forward, name="wire", daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

    def close(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(2)
        for fd in self._fds:
            os.close(fd)
        self._fds.clear()
        for ns in self._made:
            subprocess.run(["ip", "netns", "del", ns], capture_output=True, timeout=20)
        self._made.clear()

    def flap(self, up: float, down: float, until: float) -> None:
        """Take the cable down for ``down`` s, then up for ``up`` s, over and over, until the
        ``time.monotonic()`` deadline ``until``; returns with the cable up."""
        while time.monotonic() < until:
            self.down = True
            time.sleep(down)  # the fault: the cable stays down this long
            self.down = False
            time.sleep(up)  # and up this long
        self.down = False

    def _forward(self) -> None:
        a, b = self._fds
        other = {a: b, b: a}
        held: list[tuple[float, int, int, bytes]] = []  # (due, order, to fd, packet)
        order = 0
        while not self._stop.is_set():
            now = time.monotonic()
            while held and held[0][0] <= now:
                _, _, to, packet = heapq.heappop(held)
                self._write(to, packet)
            wait = min(0.05, max(0.0, held[0][0] - now)) if held else 0.05
            ready, _, _ = select.select([a, b], [], [], wait)
            for fd in ready:
                while True:
                    try:
                        packet = os.read(fd, MTU + 64)
                    except BlockingIOError:
                        break
                    except OSError:
                        return
                    if self.down or (self.loss and self._random.random() < self.loss):
                        self.dropped += 1
                        continue
                    if self.latency > 0:
                        order += 1
                        heapq.heappush(held, (time.monotonic() + self.latency, order, other[fd], packet))
                    else:
                        self._write(other[fd], packet)

    def _write(self, fd: int, packet: bytes) -> None:
        try:
            os.write(fd, packet)
            self.forwarded += 1
        except OSError:  # the device is gone or its queue is full: the packet is lost, as on a wire
            self.dropped += 1
