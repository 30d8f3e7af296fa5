"""What every long-running tool does when its router goes away: one behaviour, decided here.

echo, hz, log -f, view, record, plot and teleop keep running while the router is lost (Zenoh
reconnects the session by itself when it is back) and say so: one line when it is lost, one
when it is back, never a line per check.  With ``--exit-on-loss`` they end instead, with
RouterLost (exit code 3, as a goal whose router goes away).  Nothing here prints: ``check``
returns the line to show; the tool shows it where its output goes (stderr, a status line).
"""

from __future__ import annotations

from collections.abc import Callable

from turtlectl.runtime.client.services import RouterLost
from turtlectl.runtime.client.session import ROUTER_CHECK

EXIT_ON_LOSS_HELP = "Exit with code 3 when the router is lost, instead of waiting for it to come back."


class RouterWatch:
    """Whether the session has its router, asked (``lost()``) at most every ROUTER_CHECK s.

    ``check(now)`` (now: monotonic s) returns a line when the router was just lost or is just
    back, else None; with ``exit_on_loss`` a loss raises RouterLost instead.  ``what`` names
    what the tool stops receiving ("messages on robot/status", "log records")."""

    def __init__(self, lost: Callable[[], bool], connect: str, what: str, exit_on_loss: bool = False):
        self._lost = lost
        self.connect, self.what, self.exit_on_loss = connect, what, exit_on_loss
        self.next = 0.0  # the first check at once: a tool started without its router says so
        self.lost_since: float | None = None  # monotonic s the loss was seen, None while connected

    @property
    def lost(self) -> bool:
        """True from the check that saw the router gone until the one that sees it back."""
        return self.lost_since is not None

    def check(self, now: float) -> str | None:
        if now < self.next:
            return None
        self.next = now + ROUTER_CHECK
        gone = self._lost()
        if gone and self.lost_since is None:
            if self.exit_on_loss:
                raise RouterLost(
                    f"lost the router at {self.connect}: no more {self.what} (did `turtlectl launch` stop?)"
                )
            self.lost_since = now
            return (
                f"lost the router at {self.connect}: waiting for it to come back, no {self.what} meanwhile "
                "(--exit-on-loss exits instead)"
            )
        if not gone and self.lost_since is not None:
            lasted, self.lost_since = now - self.lost_since, None
            return f"the router at {self.connect} is back after {lasted:.1f} s: {self.what} again"
        return None


def watch(session: object, connect: str, what: str, exit_on_loss: bool = False) -> RouterWatch:
    """The RouterWatch of a client ``session`` (a zenoh.Session) of the router at ``connect``."""
    from turtlectl.runtime.client.session import router_lost

    return RouterWatch(lambda: router_lost(session), connect, what, exit_on_loss)  # type: ignore[arg-type]
