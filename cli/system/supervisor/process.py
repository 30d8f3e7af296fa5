"""One supervised child process: start, stream its output, signal, reap.

A launch file's node is a node (``node_command``) or any program (``program_command``, a
``cmd`` node: exec'd, never forked by the zygote, told who it is in NODE_NAME_VAR, DOMAIN_ENV
and CONNECT_ENV).

Children run in their own process group, so a Ctrl-C on the terminal reaches
only the supervisor, which then signals each child exactly once per step.
They are told the supervisor's pid and ask Linux to SIGTERM them if it dies.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
from typing import BinaryIO, NoReturn

from turtlectl.cli.system.supervisor.printer import Printer
from turtlectl.cli.system.supervisor.zygote import Zygote, ZygoteUnavailable
from turtlectl.nodes.kinds import KINDS, NodeKind
from turtlectl.runtime.config import ENV_VAR, SUPERVISOR_PID_VAR, NodeConfig, encode_config
from turtlectl.runtime.endpoint import CONNECT_ENV, DOMAIN_ENV

#: what a ``cmd`` node is told: its name in the launch file; with the system's domain (key prefix,
#: empty for none) and the router's endpoint in runtime.endpoint's variables, which the CLI reads too
NODE_NAME_VAR = "TURTLECTL_NODE_NAME"


class Child:
    def __init__(self, name: str, argv: list[str], env: dict[str, str], printer: Printer, cwd: str | None = None):
        self.name = name
        self.argv = argv
        self.env = env
        self.cwd = cwd or None  # where it runs (a user's node or program: the launch file's folder)
        self.printer = printer
        self.proc: subprocess.Popen[bytes] | None = None
        self._reader: threading.Thread | None = None
        self._group_killed = False
        #: its output goes to its log file only, not the terminal (set by the supervision: a start
        #: after one that failed before it was ready, whose traceback was shown already)
        self.quiet = False
        self.last_line = ""  # the last non-blank line of the current start's output (its error, after a failure)

    @property
    def pid(self) -> int | None:
        return self.proc.pid if self.proc else None

    def start(self) -> None:
        """Spawn (fork+exec, never a bare fork: the supervisor holds a Zenoh session)."""
        self.proc = subprocess.Popen(
            self.argv,
            env=self.env,
            cwd=self.cwd,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            process_group=0,
            close_fds=True,
        )
        assert self.proc.stdout is not None  # set by Popen(stdout=PIPE)
        self._read_output(self.proc.stdout)

    def _read_output(self, out: BinaryIO) -> None:
        """Stream the new child's output (a pipe) to the printer, on a thread of its own."""
        self._group_killed = False
        self.last_line = ""
        self._reader = threading.Thread(target=self._pump, args=(out,), name=f"out-{self.name}", daemon=True)
        self._reader.start()

    def _pump(self, out: BinaryIO) -> None:
        with out:
            for raw in out:
                text = raw.decode("utf-8", "replace")
                if text.strip():
                    self.last_line = text.strip()
                self.printer.line(self.name, text, terminal=not self.quiet)

    def poll(self) -> int | None:
        """The exit code if the child has exited (reaping it), else None."""
        return None if self.proc is None else self._reaped(self.proc.pid, self.proc.poll())

    def _reaped(self, pid: int, code: int | None) -> int | None:
        """``code``; once the child has exited, whatever it started is killed with it (its process
        group), so a crashed node leaves nothing behind."""
        if code is not None and not self._group_killed:
            self._group_killed = True
            try:  # the group outlives its leader while members remain; the pgid is not reused meanwhile
                os.killpg(pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        return code

    def running(self) -> bool:
        return self.pid is not None and self.poll() is None

    def send(self, sig: signal.Signals) -> None:
        """Signal the child's whole process group (it leads its own), as honcho and mirakuru do:
        whatever the node itself started gets the signal too and never outlives it."""
        pid = self.pid
        if pid is not None and self.running():
            try:
                os.killpg(pid, sig)
            except ProcessLookupError:
                pass

    def flush_output(self, timeout: float = 1.0) -> None:
        """Wait (bounded) for the rest of the child's output after it exited."""
        if self._reader is not None:
            self._reader.join(timeout)


class ZygoteChild(Child):
    """A Child forked by the zygote (cli.system.supervisor.zygote) rather than started by fork+exec:
    the same interface and guarantees (own process group, output on a pipe read here, the
    group killed once the node has exited); it is this process's child all the same (the
    zygote hands it over), reaped here.  If the zygote cannot start it (gone, no answer,
    its module failed to import there), it is started as a Child is, and the supervisor says
    why, once for each reason."""

    def __init__(self, name: str, argv: list[str], env: dict[str, str], printer: Printer, zygote: Zygote):
        super().__init__(name, argv, env, printer)
        self.zygote = zygote
        self.module = argv[-1]  # node_command's argv ends with the kind's module
        self._pid: int | None = None
        self._code: int | None = None

    @property
    def pid(self) -> int | None:
        return self._pid if self.proc is None else self.proc.pid

    def start(self) -> None:
        self.proc, self._pid, self._code = None, None, None
        read, write = os.pipe()
        try:
            self._pid = self.zygote.spawn(self.module, self.env, write, self.name)
        except ZygoteUnavailable as exc:
            os.close(read)
            if str(exc) not in self.zygote.reported:
                self.zygote.reported.add(str(exc))
                which = f"nodes running {exc.starts}" if exc.starts else "nodes"
                self.printer.system(f"{exc}; starting {which} as new processes")
            super().start()
            assert self.proc is not None  # set by Child.start
            self.zygote.handed.add(self.proc.pid)  # known: not a stray to reap
            return
        finally:
            os.close(write)
        self._read_output(os.fdopen(read, "rb"))

    def poll(self) -> int | None:
        if not self.zygote.alive:  # a start it died in may have left zombies: no Child knows them
            self.zygote.reap_strays()
        if self.proc is not None:
            return super().poll()
        if self._pid is None:
            return None
        if self._code is None:
            try:
                done, status = os.waitpid(self._pid, os.WNOHANG)
            except ChildProcessError:  # reaped already: it can only have been here
                done, status = self._pid, 1 << 8
            if done:
                self._code = os.waitstatus_to_exitcode(status)
        return self._reaped(self._pid, self._code)


def node_command(
    config: NodeConfig, supervisor_pid: int | None = None, kind: NodeKind | None = None
) -> tuple[list[str], dict[str, str]]:
    """The argv and environment that start node ``config``, the one way both ``launch`` and
    ``run`` do it: this interpreter, unbuffered, running a built-in kind's module, or a user's
    node class (``kind``, as the launch file's run resolved: a built-in's by default) through
    ``python -m turtlectl.runtime TARGET`` (runtime/__main__.py says why such a node is never forked by
    the zygote), with the config in its environment.  ``supervisor_pid``: the supervisor the
    node watches (it stops when that process dies); None for a node run on its own (``turtlectl
    run``), which watches nobody."""
    kind = kind or KINDS[config.kind]
    argv = [sys.executable, "-u", "-m", *((kind.module,) if kind.builtin else ("turtlectl.runtime", kind.target))]
    env = dict(os.environ)
    env[ENV_VAR] = encode_config(config)
    env["PYTHONUNBUFFERED"] = "1"
    if config.domain:  # a Client the node's code opens is in its system's domain
        env[DOMAIN_ENV] = config.domain
    if supervisor_pid is None:
        env.pop(SUPERVISOR_PID_VAR, None)
    else:
        env[SUPERVISOR_PID_VAR] = str(supervisor_pid)
    return argv, env


def program_command(name: str, argv: list[str], connect: str, domain: str) -> tuple[list[str], dict[str, str]]:
    """The argv and environment that start ``cmd`` node ``name``: its argv as the launch file
    resolved it, this environment without a node's config, plus its name, domain and endpoint."""
    env = {k: v for k, v in os.environ.items() if k not in (ENV_VAR, SUPERVISOR_PID_VAR)}
    env |= {NODE_NAME_VAR: name, DOMAIN_ENV: domain, CONNECT_ENV: connect, "PYTHONUNBUFFERED": "1"}
    return list(argv), env


def exec_node(config: NodeConfig, kind: NodeKind) -> NoReturn:
    """Become node ``config`` of ``kind`` (``turtlectl run``): exec it in this process, in the foreground."""
    argv, env = node_command(config, kind=kind)
    os.execve(argv[0], argv, env)
