"""The zygote's own side, in the process ``zygote.start`` forks (the design, and the supervisor's
side, are in ``cli.system.supervisor.zygote``): import every node module once, then serve the
supervisor's requests on the Unix socket, forking each node through a middle process that exits
at once, so that the node becomes the supervisor's child, and making the forked grandchild the
node, as ``python -u -m module`` would start it, once the supervisor's go has come.

Guarantees, as for a node started by ``subprocess``: each forked node leads its own process
group (set by the node and by the middle process, so that it exists before its pid is told),
has default signal handlers and an empty signal mask, stdin on /dev/null and stdout and stderr
on the supervisor's pipe, and asks Linux for SIGTERM when the supervisor dies; the zygote asks
for SIGTERM when the supervisor dies and exits when the supervisor's end of the socket closes.
"""

from __future__ import annotations

# Only what forking costs nothing to import: cli.entry imports this module (through zygote) before
# typer; the rest is imported where used.
import _socket
import os
import signal
import sys
from types import ModuleType

_PR_SET_PDEATHSIG = 1
_PR_SET_NAME = 15  # the name ps -o comm and top show (a forked node keeps the supervisor's argv)
MAX_MESSAGE = 1 << 20  # bytes: a request carries a whole environment
#: what the nodes import on first use while they start, imported by the zygote once for all:
#: the idna codec (getaddrinfo of a host name), numpy.random (numpy 2 loads it lazily; the
#: obstacle detector's generator); about 35 ms of each node's start
WARM = ("encodings.idna", "numpy.random")


def prctl(option: int, arg: int | bytes) -> bool:
    """Linux's prctl; whether it succeeded."""
    import ctypes  # here: the supervisor imports this module before typer, as early as it can

    try:
        return int(ctypes.CDLL(None, use_errno=True).prctl(option, arg, 0, 0, 0)) == 0
    except (OSError, AttributeError):
        return False


def _pdeathsig(sig: signal.Signals) -> None:
    prctl(_PR_SET_PDEATHSIG, int(sig))


def close_inherited(keep: int) -> None:
    """Close every descriptor above stderr but ``keep``: what the shell or the supervisor had open
    must not live on in the zygote and its nodes (a Popen child gets close_fds=True; without this a
    shell's fd 9, for one, would be held open by every node)."""
    os.closerange(3, keep)
    os.closerange(keep + 1, os.sysconf("SC_OPEN_MAX"))


def serve(fd: int, supervisor: int, names: list[str] | None) -> int:
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
    prctl(_PR_SET_NAME, b"turtle-zygote")

    if names is None:
        from turtlectl.nodes.kinds import KINDS

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
            data, fds, _flags, _addr = socket.recv_fds(sock, MAX_MESSAGE, 2)
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
        prctl(_PR_SET_NAME, str(request.get("name") or module.__name__.rpartition(".")[2]).encode()[:15])
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
