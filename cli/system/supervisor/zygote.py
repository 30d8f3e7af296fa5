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
node (it only means the next starts are by exec; the first zygote design tied nodes to it).

A node runs only once the supervisor knows it.  A forked node waits for one byte on its "go"
pipe, which the supervisor writes once the zygote has told it the node's pid (by then the
node is its child), and closes unwritten if the start failed; a node that reads end-of-file
(the zygote died while forking it, or the supervisor died) exits at once, without running.
So killing the zygote or the supervisor mid-fork leaves no node running untracked, and the
zombies of such starts are reaped (``reap_strays``).

Guarantees, as for a node started by ``subprocess``: each forked node leads its own process
group (set by the node and by the middle process, so that it exists before its pid is told),
has default signal handlers and an empty signal mask, stdin on /dev/null and stdout and stderr
on the supervisor's pipe, and asks Linux for SIGTERM when the supervisor dies; the zygote asks
for SIGTERM when the supervisor dies and exits when the supervisor's end of the socket closes.

The supervisor side is ``Zygote`` (the socket, a reader thread, the answers).
"""

from __future__ import annotations

# Only what forking costs nothing to import: cli.entry imports this module before typer, and
# every millisecond before the fork is one the zygote starts later; the rest is imported where used.
import _socket
import os
import signal
import sys
from collections.abc import Callable
from types import ModuleType

_PR_SET_PDEATHSIG = 1
_PR_SET_NAME = 15  # the name ps -o comm and top show (a forked node keeps the supervisor's argv)
_PR_SET_CHILD_SUBREAPER = 36  # orphans below this process become its children (Linux 3.4+)
_MAX_MESSAGE = 1 << 20  # bytes: a request carries a whole environment
#: what the nodes import on first use while they start, imported by the zygote once for all:
#: the idna codec (getaddrinfo of a host name), numpy.random (numpy 2 loads it lazily; the
#: obstacle detector's generator); about 35 ms of each node's start
WARM = ("encodings.idna", "numpy.random")
START_TIMEOUT = 10.0  # s a request may wait for its answer (the zygote may still be importing)

#: set in the early zygote, taken by the supervisor (``take``)
_early: Zygote | None = None


class ZygoteUnavailable(Exception):
    """The zygote cannot start this node (it is gone, did not answer, or lacks the module).
    ``starts``: what will start as new processes instead ("" for every node)."""

    def __init__(self, message: str, starts: str = ""):
        super().__init__(message)
        self.starts = starts


def _prctl(option: int, arg: int | bytes) -> bool:
    """Linux's prctl; whether it succeeded."""
    import ctypes  # here: the supervisor imports this module before typer, as early as it can

    try:
        return int(ctypes.CDLL(None, use_errno=True).prctl(option, arg, 0, 0, 0)) == 0
    except (OSError, AttributeError):
        return False


def _pdeathsig(sig: signal.Signals) -> None:
    _prctl(_PR_SET_PDEATHSIG, int(sig))


# -- the supervisor's side ------------------------------------------------------------------


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
                data = self.sock.recv(_MAX_MESSAGE)
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
    if pid == 0:  # the zygote: never returns into the caller's code (nor does a node it forks, see _become)
        code = 1
        try:
            signal.signal(signal.SIGINT, signal.SIG_IGN)  # first: a Ctrl-C is the supervisor's to handle
            os.close(ours)
            _close_inherited(keep=theirs)
            code = _serve(theirs, supervisor, modules)
        except BaseException:  # noqa: BLE001 - nothing of the zygote may unwind into the caller
            import traceback

            traceback.print_exc()
        finally:
            os._exit(code)
    os.close(theirs)
    if not _prctl(_PR_SET_CHILD_SUBREAPER, 1):  # after the fork: the zygote imports meanwhile
        os.close(ours)  # without it, forked nodes would be orphans: no zygote (it exits on EOF)
        return None
    return Zygote(pid, ours)


def _close_inherited(keep: int) -> None:
    """Close every descriptor above stderr but ``keep``: what the shell or the supervisor had open
    must not live on in the zygote and its nodes (a Popen child gets close_fds=True; a review of
    issue 10 found a shell's fd 9 held open by every node)."""
    os.closerange(3, keep)
    os.closerange(keep + 1, os.sysconf("SC_OPEN_MAX"))


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


# -- the zygote's side ------------------------------------------------------------------------


def _serve(fd: int, supervisor: int, names: list[str] | None) -> int:
    """The zygote's life: import every node module, then fork nodes on request until the
    supervisor goes away.  Returns its exit code."""
    import importlib
    import json
    import socket

    sock = socket.socket(fileno=fd)
    _pdeathsig(signal.SIGTERM)
    if os.getppid() != supervisor:  # the supervisor died before the request for its death took
        return 0
    os.setpgid(0, 0)  # a Ctrl-C on the terminal is for the supervisor, which then signals the nodes
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    devnull = os.open(os.devnull, os.O_RDWR)
    os.dup2(devnull, 0)
    os.dup2(devnull, 1)  # stderr stays the supervisor's, for the zygote's own failures
    os.close(devnull)
    _prctl(_PR_SET_NAME, b"turtle-zygote")

    if names is None:
        from nodes.kinds import KINDS

        names = [kind.module for kind in KINDS.values()]
    modules: dict[str, ModuleType] = {}
    broken: dict[str, str] = {}
    for name in names:
        try:
            modules[name] = importlib.import_module(name)
        except Exception as exc:  # noqa: BLE001 - such a node is started as a process, which reports it
            broken[name] = f"the zygote cannot import {name}: {type(exc).__name__}: {exc}"
    for name in WARM:
        try:
            importlib.import_module(name)
        except ImportError:
            pass

    while True:
        try:
            data, fds, _flags, _addr = socket.recv_fds(sock, _MAX_MESSAGE, 2)
        except OSError:
            data, fds = b"", []
        if not data:
            return 0  # the supervisor closed its end, or exited
        request = json.loads(data)
        answer: dict[str, object] = {"id": request["id"]}
        module = modules.get(request["module"])
        if module is None or len(fds) != 2:
            answer["error"] = broken.get(request["module"], f"no module {request['module']!r} in the zygote")
        else:
            try:
                answer["pid"] = _fork_node(module, request, fds, sock, supervisor)
            except OSError as exc:
                answer["error"] = f"the zygote could not fork: {exc}"
        for fd in fds:
            os.close(fd)
        sock.send(json.dumps(answer).encode())


def _fork_node(
    module: ModuleType, request: dict[str, object], fds: list[int], sock: _socket.socket, supervisor: int
) -> int:
    """Fork the node through a middle process that exits at once, so that the node becomes the
    supervisor's child (it is a subreaper); the node's pid, its process group already made."""
    read, write = os.pipe()
    middle = os.fork()
    if middle == 0:
        code = 1
        try:
            os.close(read)
            pid = os.fork()
            if pid == 0:
                os.close(write)
                _become(module, request, fds, sock, supervisor)
            try:  # the group exists before anyone is told the pid (the node sets it too)
                os.setpgid(pid, pid)
            except OSError:
                pass
            os.write(write, str(pid).encode())
            code = 0
        finally:
            os._exit(code)
    os.close(write)
    try:
        told = b""
        while chunk := os.read(read, 32):
            told += chunk
    finally:
        os.close(read)
        os.waitpid(middle, 0)
    if not told:
        raise OSError("the middle process did not fork the node")
    return int(told)


def _become(
    module: ModuleType, request: dict[str, object], fds: list[int], sock: _socket.socket, supervisor: int
) -> None:
    """In a freshly forked grandchild of the zygote: wait for the supervisor's go, become the
    node, as ``python -u -m module`` would be, run its ``main()``, and exit (never returns into
    the zygote's code: ``os._exit``)."""
    import io
    import traceback

    out, go = fds
    code = 1
    try:
        os.setpgid(0, 0)
        sock.close()
        if os.read(go, 1) != b"g":  # the supervisor gave up on this start, or is gone: never run
            os._exit(0)
        os.close(go)
        # the go comes after the middle process has exited, so the supervisor is our parent now
        # (a parent-death signal asked for earlier would have fired as the middle process exited)
        _pdeathsig(signal.SIGTERM)
        if os.getppid() != supervisor:  # the supervisor died meanwhile (or is no subreaper)
            os._exit(0)
        for sig in (signal.SIGTERM, signal.SIGCHLD, signal.SIGHUP, signal.SIGQUIT):
            signal.signal(sig, signal.SIG_DFL)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.pthread_sigmask(signal.SIG_SETMASK, [])
        devnull = os.open(os.devnull, os.O_RDONLY)
        os.dup2(devnull, 0)
        os.close(devnull)
        os.dup2(out, 1)
        os.dup2(out, 2)
        os.close(out)
        sys.stdout = io.TextIOWrapper(open(1, "wb", 0, closefd=False), write_through=True)  # noqa: SIM115
        sys.stderr = io.TextIOWrapper(
            open(2, "wb", 0, closefd=False),  # noqa: SIM115
            errors="backslashreplace",
            write_through=True,
        )
        os.environ.clear()
        os.environ.update(request["env"])  # type: ignore[call-overload]
        sys.argv = [getattr(module, "__file__", None) or module.__name__]
        _prctl(_PR_SET_NAME, str(request.get("name") or module.__name__.rpartition(".")[2]).encode()[:15])
        try:
            module.main()
            code = 0
        except SystemExit as exc:
            code = _exit_code(exc)
        except BaseException:  # noqa: BLE001 - as the interpreter would: the traceback, exit 1
            traceback.print_exc()
            code = 1
        _finalize()
    finally:
        os._exit(code)


def _exit_code(exc: SystemExit) -> int:
    if exc.code is None:
        return 0
    if isinstance(exc.code, int):
        return exc.code
    print(exc.code, file=sys.stderr)
    return 1


def _finalize() -> None:
    """What the interpreter does at exit, for a process that must leave with ``os._exit``:
    wait for its non-daemon threads, run the exit handlers, flush its output."""
    import atexit
    import threading

    try:
        threading._shutdown()  # type: ignore[attr-defined]
    except Exception:  # noqa: BLE001
        pass
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
