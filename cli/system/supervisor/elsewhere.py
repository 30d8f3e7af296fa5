"""The nodes a supervisor did not start (another host's, another supervisor's, a `turtlectl run`),
as their liveliness tokens come and go: one line when one is first seen, when it leaves, and
when it comes back (pure: the supervisor's shell hands over the tokens; cli.system.supervisor.manager).

A token leaves when its process ends or when its host stops answering (the router drops a
peer's tokens when the link to it is lost), so "left" is said for a crash, a stop and a
partition alike; a node that comes back under a new pid (respawned there) or the same one (the
link restored) is "back".
"""

from __future__ import annotations


class Elsewhere:
    """Who runs outside this supervisor, by name: ``seen`` each token put or deleted, and print
    the line it returns (None: nothing new to say)."""

    def __init__(self) -> None:
        self.running: dict[str, tuple[int, str]] = {}  # name -> (pid, host) of its live token
        self.left: set[str] = set()  # names that ran and left (their return is "back")

    def seen(self, alive: bool, name: str, pid: int, host: str) -> str | None:
        where = f"pid {pid}" + (f" on {host}" if host else "")
        if alive:
            if self.running.get(name) == (pid, host):
                return None  # the same token again
            self.running[name] = (pid, host)
            if name in self.left:
                self.left.discard(name)
                return f"{name} is back ({where}; not started here)"
            return f"{name} runs elsewhere ({where}; not started here)"
        if self.running.get(name, (None, None))[0] != pid:
            return None  # an earlier process of that name, already replaced
        del self.running[name]
        self.left.add(name)
        return f"{name} left ({where}; not started here): its topics and services are gone until it is back"
