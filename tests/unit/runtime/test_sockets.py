"""runtime.sockets: lingering TCP sockets of the process lose SO_LINGER; others are left alone."""

from __future__ import annotations

import socket
import struct

from turtlectl.runtime.sockets import unlinger_new_sockets


def linger(sock: socket.socket) -> tuple[int, int]:
    return struct.unpack("ii", sock.getsockopt(socket.SOL_SOCKET, socket.SO_LINGER, 8))


def test_a_lingering_tcp_socket_loses_its_linger_and_is_seen_once():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as tcp, socket.socket(socket.AF_UNIX) as unix:
        tcp.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 10))
        unix.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 10))
        seen: set[str] = set()
        assert unlinger_new_sockets(seen) >= 1
        assert linger(tcp)[0] == 0
        assert linger(unix)[0] == 1  # not a network socket: no link of Zenoh's, left as it is
        tcp.fileno()  # still open: only the duplicate was closed
        tcp.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 10))
        assert unlinger_new_sockets(seen) == 0  # already seen: a sweep looks only at new sockets
        assert linger(tcp)[0] == 1


def test_closed_sockets_are_forgotten():
    seen: set[str] = set()
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM):
        unlinger_new_sockets(seen)
        during = set(seen)
    unlinger_new_sockets(seen)
    assert len(seen) < len(during)
