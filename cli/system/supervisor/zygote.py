"""The zygote: one helper process that imports every node module once, then forks a node per
request, so that a launch pays for numpy, zenoh and msgspec once instead of once per node.

Who forks what.  The supervisor forks the zygote (``start``) as early as it can (``cli.entry``,
before typer is imported, or else ``Supervisor.run``), always before it opens a Zenoh session:
a process that has opened one is never forked.  The zygote never opens a session either; it
imports the node modules, then serves requests on a Unix socket (SOCK_SEQPACKET, one JSON
message each): ``start`` (a node module and its environment, built by
``process.node_command``, with the write end of the pipe its output goes to and the read end
of its "go" pipe, passed with ``send_fds``) answered with ``started`` (its pid) or ``failed``.

Whose child a node is.  The zygote forks twice: a short-lived middle process forks the node and
exits, and Linux hands the node to the nearest "child subreaper" above it, the supervisor
(``start`` makes it one).  So every node is the supervisor's own child, as one started by
``subprocess`` is: the supervisor reaps it and reads its real exit code, the node's
parent-death signal and parent watch point at the supervisor, and killing the zygote ends no
node (it only means the next starts are by exec).

A node runs only once the supervisor knows it.  A forked node waits for one byte on its "go"
pipe, which the supervisor writes once the zygote has told it the node's pid (by then the
node is its child), and closes unwritten if the start failed; a node that reads end-of-file
(the zygote died while forking it, or the supervisor died) exits at once, without running.
So killing the zygote or the supervisor mid-fork leaves no node running untracked, and the
zombies of such starts are reaped (``reap_strays``).

This module is the supervisor's side: ``start`` (the fork), and ``Zygote`` (the socket, a reader
thread, the answers).  The zygote's own side, its loop and the forking of a node (and what a
forked node is guaranteed), is ``cli.system.supervisor.zygote_server``.
"""

from __future__ import annotations

# Only what forking costs nothing to import: cli.entry imports this module before typer, and
# every millisecond before the fork is one the zygote starts later; the rest is imported where used.
import _socket
import os
import signal
from collections.abc import Callable

from turtlectl.cli.system.supervisor.zygote_server import MAX_MESSAGE, close_inherited, prctl, serve

_PR_SET_CHILD_SUBREAPER = 36  # orphans below this process become its children (Linux 3.4+)
START_TIMEOUT = 10.0  # s a request may wait for its answer (the zygote may still be importing)

#: set in the early zygote, taken by the supervisor (``take``)
_early: Zygote | None = None


class ZygoteUnavailable(Exception):
    """The zygote cannot start this node (it is gone, did not answer, or lacks the module).
    ``starts``: what will start as new processes instead ("" for every node)."""

    def __init__(self, message: str, starts: str = ""):
        super().__init__(message)
        self.starts = starts


class Zygote:
    """The supervisor's handle on a running zygote: ``spawn`` a node.  ``on_exit(text)``, if
    set, is told on the zygote's own thread when the zygote ends other than by ``close``."""

    def __init__(self, pid: int, fd: int):
        import socket
        import threading

        self.pid = pid
        self.sock = socket.socket(fileno=fd)
        self.reported: set[str] = set()  # why nodes start without it, each said once by the supervisor
        self.handed: set[int] = set()  # pids of the nodes it started (and of their replacements by exec)
        self._cond = threading.Condition()
        self._answers: dict[int, dict[str, object]] = {}
        self._next = 0
        self._alive = True
        self._closing = False
        self.ended = "has exited"  # how, once it has: "was killed by SIGKILL", "exited with code 1"
        self.on_exit: Callable[[str], None] | None = None
        self._send_lock = threading.Lock()
        self._strays_checked = 0.0
        self._reader = threading.Thread(target=self._read, name="zygote", daemon=True)
        self._reader.start()

    @property
    def alive(self) -> bool:
        return self._alive

    def _read(self) -> None:
        import json

        while True:
            try:
                data = self.sock.recv(MAX_MESSAGE)
            except OSError:
                data = b""
            if not data:
                break
            message = json.loads(data)
            with self._cond:
                self._answers[message["id"]] = message
                self._cond.notify_all()
        try:
            _, status = os.waitpid(self.pid, 0)  # our child: reap it
            code = os.waitstatus_to_exitcode(status)
            self.ended = f"was killed by {signal.Signals(-code).name}" if code < 0 else f"exited with code {code}"
        except (ChildProcessError, ValueError):
            pass
        with self._cond:
            self._alive = False
            self._cond.notify_all()
        if not self._closing and self.on_exit is not None:
            gone = f"the zygote (pid {self.pid}) {self.ended}"
            self.reported.add(gone)  # said now, not again when a node next starts
            self.on_exit(f"{gone}; running nodes go on, the next ones start as new processes")

    def spawn(self, module: str, env: dict[str, str], out: int, name: str = "", timeout: float = START_TIMEOUT) -> int:
        """Fork a node running ``module``'s ``main()`` with ``env``, its output on fd ``out``; its pid.
        ``name``: what ``ps -o comm`` shows (the module's last part if empty)."""
        import json
        import socket

        with self._cond:
            if not self._alive:
                raise ZygoteUnavailable(f"the zygote (pid {self.pid}) {self.ended}")
            self._next += 1
            ident = self._next
        request = json.dumps({"id": ident, "module": module, "env": env, "name": name}).encode()
        go_read, go_write = os.pipe()
        try:
            try:
                with self._send_lock:
                    socket.send_fds(self.sock, [request], [out, go_read])
            except OSError as exc:
                raise ZygoteUnavailable(f"the zygote (pid {self.pid}) cannot be reached: {exc}") from None
            finally:
                os.close(go_read)
            pid = self._answer(ident, module, timeout)
            self.handed.add(pid)
            try:
                os.write(go_write, b"g")  # it is known now: let it run
            except OSError:
                pass  # it is gone already: its exit code tells why
            return pid
        finally:
            os.close(go_write)  # unwritten: the node, if any, exits without running

    def _answer(self, ident: int, module: str, timeout: float) -> int:
        with self._cond:
            answered = self._cond.wait_for(lambda: ident in self._answers or not self._alive, timeout)
        if not answered:  # hung: ended, so that no later start waits for it too
            try:
                os.kill(self.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            raise ZygoteUnavailable(f"the zygote (pid {self.pid}) did not answer within {timeout:g} s; ended it")
        with self._cond:
            answer = self._answers.pop(ident, None)
        if answer is None:
            raise ZygoteUnavailable(f"the zygote (pid {self.pid}) {self.ended}")
        if "pid" not in answer:
            raise ZygoteUnavailable(str(answer.get("error", "the zygote could not start it")), starts=module)
        return int(str(answer["pid"]))

    def reap_strays(self) -> None:
        """Reap the children of this process that no Child knows (the middle process and the
        node of a start the zygote died in); those still running are left alone."""
        import pathlib
        import time

        now = time.monotonic()
        if now - self._strays_checked < 1.0:  # at most once a second: it reads /proc
            return
        self._strays_checked = now
        known = self.handed | {self.pid}
        for task in pathlib.Path("/proc/self/task").iterdir():
            try:
                children = [int(c) for c in (task / "children").read_text().split()]
            except OSError:
                continue
            for pid in children:
                if pid not in known and not _alive(pid):
                    try:
                        os.waitpid(pid, os.WNOHANG)
                    except ChildProcessError:
                        pass

    def close(self) -> None:
        """Let it go: it exits once the socket closes (its nodes are the supervisor's to stop)."""
        self._closing = True
        try:
            self.sock.shutdown(_socket.SHUT_RDWR)
        except OSError:
            pass
        self._reader.join(2.0)
        self.sock.close()


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(") ", 1)[1][0] != "Z"
    except OSError:
        return False


def start(modules: list[str] | None = None) -> Zygote | None:
    """Fork the zygote now; None if it cannot be.  The caller must have opened no Zenoh session
    and must be single-threaded (only the calling thread is copied); it becomes a child
    subreaper, so that the nodes forked below it become its children (see the module
    docstring) and must reap them.  ``modules``: what it imports and can start (default:
    every kind's module, nodes.kinds.KINDS)."""
    try:
        ours, theirs = (s.detach() for s in _socket.socketpair(_socket.AF_UNIX, _socket.SOCK_SEQPACKET))
        supervisor = os.getpid()
        pid = os.fork()
    except OSError:
        return None
    if pid == 0:  # the zygote: never returns into the caller's code (nor does a node it forks, see zygote_server)
        code = 1
        try:
            signal.signal(signal.SIGINT, signal.SIG_IGN)  # first: a Ctrl-C is the supervisor's to handle
            os.close(ours)
            close_inherited(keep=theirs)
            code = serve(theirs, supervisor, modules)
        except BaseException:  # noqa: BLE001 - nothing of the zygote may unwind into the caller
            import traceback

            traceback.print_exc()
        finally:
            os._exit(code)
    os.close(theirs)
    if not prctl(_PR_SET_CHILD_SUBREAPER, 1):  # after the fork: the zygote imports meanwhile
        os.close(ours)  # without it, forked nodes would be orphans: no zygote (it exits on EOF)
        return None
    return Zygote(pid, ours)


def start_early() -> None:
    """``cli.entry`` for ``turtlectl launch``: the zygote starts importing while typer does."""
    global _early
    if _early is None:
        _early = start()


def take() -> Zygote | None:
    """The zygote started early, or one started now (then the caller must not hold a session)."""
    global _early
    zygote, _early = _early, None
    return zygote if zygote is not None and zygote.alive else start()
