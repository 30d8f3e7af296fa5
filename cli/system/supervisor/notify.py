"""The launch's state for whoever started it, in systemd's notify protocol (``sd_notify(3)``):
when ``NOTIFY_SOCKET`` names a Unix datagram socket, the supervisor sends it ``READY=1`` once
every node is ready (or every node that will be), a datagram for each node's exit, and
``STOPPING=1`` when it stops.  A systemd unit with ``Type=notify`` starts ``turtlectl launch``
as a service that is up when its nodes are; ``turtlectl.testing.LaunchedSystem`` waits on the
same datagrams.  Each is ``KEY=value`` lines:

* ``READY=1`` and ``STATUS=<the ready line>``;
* a node's exit: ``X_TURTLECTL_NODE=<name>``, ``X_TURTLECTL_EXIT=<code>`` (a signal: minus its
  number) and ``STATUS=<name> <how it ended>``;
* ``STOPPING=1`` and ``STATUS=stopping``.

The variable is taken out of the environment when read, as ``sd_notify``'s
``unset_environment`` does, so the nodes started after it do not inherit it.  A datagram that
cannot be sent is dropped: telling is never a reason to stop the system.
"""

from __future__ import annotations

import os
import socket

NOTIFY_SOCKET = "NOTIFY_SOCKET"
NODE = "X_TURTLECTL_NODE"
EXIT = "X_TURTLECTL_EXIT"


class Notifier:
    """Sends the notify datagrams to ``address`` (a path, or ``@name`` for an abstract socket);
    ``address`` None: sends nothing."""

    def __init__(self, address: str | None = None):
        self.address = address

    @classmethod
    def from_environment(cls) -> Notifier:
        """The notifier of ``$NOTIFY_SOCKET``, taken out of this process's environment."""
        return cls(os.environ.pop(NOTIFY_SOCKET, None) or None)

    def ready(self, status: str) -> None:
        self._send({"READY": "1", "STATUS": status})

    def exited(self, name: str, code: int, how: str) -> None:
        """Node ``name`` ended with ``code`` (``how``: the supervisor's words for it)."""
        self._send({NODE: name, EXIT: str(code), "STATUS": f"{name} {how}"})

    def stopping(self) -> None:
        self._send({"STOPPING": "1", "STATUS": "stopping"})

    def _send(self, fields: dict[str, str]) -> None:
        if not self.address:
            return
        target = "\0" + self.address[1:] if self.address.startswith("@") else self.address
        text = "".join(f"{key}={value.replace(chr(10), ' ')}\n" for key, value in fields.items())
        try:
            with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as sock:
                sock.sendto(text.encode(), target)
        except OSError:
            pass


def parse(datagram: bytes) -> dict[str, str]:
    """A notify datagram's fields (lines without ``=`` are ignored)."""
    fields = {}
    for line in datagram.decode(errors="replace").splitlines():
        key, sep, value = line.partition("=")
        if sep:
            fields[key] = value
    return fields
