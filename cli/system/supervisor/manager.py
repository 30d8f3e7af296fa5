"""The supervisor's outer layer: runs a router (or joins one), opens this run's log folder,
turns SIGINT/SIGTERM into a stop and the nodes' liveliness tokens into readiness, and hands
the rest to the supervision policy (cli.system.supervisor.supervision: start, watch, respawn,
stop), whose children are real processes (cli.system.supervisor.process) in their own process
groups, told to die with the supervisor.

Shutdown escalates SIGINT -> SIGTERM -> SIGKILL with the launch file's waits, each child
getting each signal once, and no child outlives the supervisor.  A child that has not
announced itself yet is still importing and gets SIGTERM first.  Never prints directly:
everything goes through the Printer.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import tempfile
from pathlib import Path
from typing import Any

import msgspec
import zenoh

from turtlectl import cli
from turtlectl.cli.system import access, certs
from turtlectl.cli.system.launchfile import LaunchPlan
from turtlectl.cli.system.overrides import node_config
from turtlectl.cli.system.supervisor import logs, zygote
from turtlectl.cli.system.supervisor.notify import Notifier
from turtlectl.cli.system.supervisor.printer import Printer
from turtlectl.cli.system.supervisor.process import Child, ZygoteChild, node_command, program_command
from turtlectl.cli.system.supervisor.router import join_router, open_router
from turtlectl.cli.system.supervisor.supervision import Supervision
from turtlectl.messages import DecodeError, ParameterEvent, decode
from turtlectl.messages.keys import NODE_TOKEN_PREFIX, PARAMETER_EVENTS, domain_token, parse_node_token
from turtlectl.runtime.client import credentials
from turtlectl.runtime.client.errors import BadInput, CannotStart, ExitCode, TurtlectlError
from turtlectl.runtime.config import ENV_VAR, PROJECT_VAR, Credentials, NodeConfig, encode_config
from turtlectl.runtime.endpoint import TLS_ENV
from turtlectl.runtime.session import close_session, listen_hosts


class Supervisor:
    """``port`` given: run a router on ``host``:port.  ``port`` None: join the router at ``connect``.
    ``log_parent``: where this run's log folder goes, made once the router is up (None: no files)."""

    def __init__(
        self,
        plan: LaunchPlan,
        printer: Printer,
        port: int | None,
        connect: str,
        domain: str = "",
        host: str = "127.0.0.1",
        log_parent: Path | None = None,
        persist: bool = False,
        log_level: str = "INFO",
        secure: bool = False,
        tls: Path | None = None,
        deny_hosts: tuple[str, ...] = (),
    ):
        self.plan = plan
        self.persist = persist  # a node started again keeps the parameters set at run time
        self.log_level = log_level
        # --secure: a login for each node, one for local clients, the router's list of users
        self.logins: dict[str, Credentials] = {}  # node -> its login
        self.client_logins: dict[str, Credentials] = {}  # role -> its login
        if secure and plan.commands:
            name = next(iter(plan.commands))
            raise BadInput(f"{name} runs a program (cmd), which has no login: a --secure system runs only nodes")
        if secure:
            names = [e.name for e in plan.launch.node] + list(plan.elsewhere)  # nodes of other hosts log in too
            self.logins = {name: credentials.new_credentials(credentials.node_user(name)) for name in names}
            self.client_logins = {role: credentials.new_credentials(role) for role in access.ROLES}
        elif connect:  # joining a --secure system: the logins it made for these nodes (on another host)
            found = {e.name: credentials.node_login(connect, e.name) for e in plan.launch.node}
            self.logins = {name: login for name, login in found.items() if login is not None}
        self.private: Path | None = None  # the folder of the router's list of users
        self.published = False  # this launch's logins are in the credentials file
        self.log_parent = log_parent
        self.port = port
        self.host = host
        self.tls = tls  # the folder of `turtlectl certs`: the router listens on tls/, mutual TLS
        self.deny_hosts = list(deny_hosts)  # hosts issued a certificate in tls/hosts/ that are shut out
        self.endpoint = f"{'tls' if tls else 'tcp'}/{host}:{port}" if port is not None else connect
        self.domain = domain
        self.printer = printer
        self.supervision = Supervision(
            plan, printer, self._child, since=cli.STARTED, notifier=Notifier.from_environment()
        )
        self.zygote: zygote.Zygote | None = None

    # -- lifecycle ----------------------------------------------------------
    def _open(self) -> zenoh.Session:
        if self.port is None:  # a --secure system's router: its viewer login (watching its nodes come)
            return join_router(self.endpoint, credentials.for_endpoint(self.endpoint, as_role="viewer"))
        if not self.client_logins:
            return open_router(self.port, self.host, "launch")
        self.private = Path(tempfile.mkdtemp(prefix="turtlectl-secure-"))  # 0700
        users = credentials.write_users(self.private, [*self.logins.values(), *self.client_logins.values()])
        kinds = self.plan.kinds | self.plan.elsewhere
        rights = {
            login.user: access.node_rights(name, kinds[name], self.plan.remaps.get(name))
            for name, login in self.logins.items()
        }
        goals = access.launch_goal_services(kinds, self.plan.remaps)  # the operator sends goals to each
        rights |= {login.user: access.client_rights(role, goals) for role, login in self.client_logins.items()}
        tls = None
        if self.tls is not None:
            tls = str(self.tls.resolve())
            os.environ[TLS_ENV] = tls  # the nodes (started from now on) show its client certificate
        names = certs.allowed_common_names(self.tls, self.deny_hosts) if self.tls and self.deny_hosts else None
        rules = access.access_control(rights, self.domain, names)
        session = open_router(self.port, self.host, "launch", str(users), rules, tls)
        remote = {
            credentials.NODE_ENTRY.format(name): self.logins[name] for name in self.plan.elsewhere
        }  # for the host that runs them: copied with the clients' entry
        for endpoint in self._endpoints():  # the listened address's, and loopback's beside it
            where = credentials.publish(endpoint, self.client_logins | remote)
        self.published = True
        self.printer.system(
            f"secure: only logged-in sessions join, each allowed what its node or role needs; clients log in with {where}"
        )
        return session

    def _endpoints(self) -> list[str]:
        """Every endpoint its router listens on (runtime.session.listen_hosts)."""
        scheme = self.endpoint.split("/", 1)[0]
        return [f"{scheme}/{h}:{self.port}" for h in listen_hosts(self.host)]

    def _forget_logins(self) -> None:
        if self.published:  # only what this launch wrote: a launch that failed on a busy port wrote nothing
            self.published = False
            try:
                for endpoint in self._endpoints():
                    credentials.withdraw(endpoint)
            except OSError as exc:
                self.printer.system(f"warning: could not remove this system's login from the credentials file: {exc}")
        if self.private is not None:
            shutil.rmtree(self.private, ignore_errors=True)
            self.private = None

    def _open_logs(self) -> None:
        """This run's log folder, made only now that the router is up (a launch that cannot
        start leaves nothing behind), and the oldest run folders beyond keep_logs removed."""
        if self.log_parent is None:
            self.printer.system(f"launch file {self.plan.source}")
            return
        folder = logs.run_folder(self.log_parent)
        names = [e.name for e in self.plan.launch.node]
        try:
            self.printer.log_to(folder, names)
        except OSError as exc:
            raise CannotStart(f"cannot write logs to {folder}: {exc.strerror or exc}") from None
        self.printer.system(f"launch file {self.plan.source}; logs in {folder}")
        try:
            logs.prune(self.log_parent, self.plan.launch.supervisor.keep_logs, folder)
        except OSError as exc:
            self.printer.system(
                f"warning: could not remove old run folders in {self.log_parent}: {exc.strerror or exc}"
            )

    def run(self) -> int:
        """Run until stopped; returns the exit code. Raises a TurtlectlError if it cannot start."""
        # before any session opens: a process that has opened one is never forked
        self.zygote = zygote.take()
        if self.zygote is not None:
            self.zygote.on_exit = self.printer.system
        try:
            session = self._open()
        except BaseException:
            self._forget_logins()
            self._close_zygote()
            raise
        try:
            self._open_logs()
        except TurtlectlError:
            close_session(session)
            self._forget_logins()
            self._close_zygote()
            raise
        previous = {sig: signal.signal(sig, self._on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
        try:
            prefix = f"{self.domain}/" if self.domain else ""
            watcher = session.liveliness().declare_subscriber(
                f"{prefix}{NODE_TOKEN_PREFIX}/**", self._on_token, history=True
            )
            changes = (
                session.declare_subscriber(f"{prefix}{PARAMETER_EVENTS}", self._on_change) if self.persist else None
            )
            # outside the namespace (this session has none): clients without --domain find the domain
            announced = session.liveliness().declare_token(domain_token(self.domain)) if self.domain else None
            count = len(self.plan.launch.node)
            listening = " and ".join(self._endpoints()) if self.port is not None else ""
            where = f"router listening on {listening}" if listening else f"joining {self.endpoint}"
            domain = f" in domain {self.domain!r}" if self.domain else ""
            self.printer.system(f"{where}{domain}; starting {count} node{'s' * (count != 1)}")
            code = self.supervision.run()
            watcher.undeclare()
            if changes is not None:
                changes.undeclare()
            if announced is not None:
                announced.undeclare()
        finally:
            for sig, handler in previous.items():
                signal.signal(sig, handler)
            if not close_session(session):
                self.printer.system("router session did not close in time")
            self._forget_logins()
            self._close_zygote()
        self.printer.system(f"stopped ({self.supervision.stop_reason}); exit code {int(code)}")
        return int(code)

    def _close_zygote(self) -> None:
        if self.zygote is not None:
            self.zygote.close()
            self.zygote = None

    def stop(self, reason: str, code: ExitCode = ExitCode.OK) -> None:
        self.supervision.stop(reason, code)

    def _on_signal(self, signum: int, _frame: Any) -> None:
        self.stop(f"received {signal.Signals(signum).name}")

    def _on_token(self, sample: zenoh.Sample) -> None:  # Zenoh thread: hand it over only
        key = str(sample.key_expr)
        if self.domain:
            key = key.removeprefix(f"{self.domain}/")
        info = parse_node_token(key)
        if info is not None:
            self.supervision.announce(sample.kind == zenoh.SampleKind.PUT, info.name, info.pid, info.host)

    def _on_change(self, sample: zenoh.Sample) -> None:  # Zenoh thread: --persist only
        """A node's parameter changed at run time: start it with the new value from now on
        (its config in the child's environment, read at each start)."""
        try:
            event = decode(sample.payload.to_bytes(), ParameterEvent)
        except DecodeError:
            return
        child = self.supervision.children.get(event.node)
        params = self.plan.params.get(event.node)
        if child is None or params is None:
            return
        *path, last = event.name.split(".")
        table = params
        for part in path:
            table = table.setdefault(part, {})
        table[last] = event.new_value
        child.env[ENV_VAR] = encode_config(self._config(event.node))
        self.printer.system(
            f"{event.node} {event.name} = {json.dumps(event.new_value)} kept for its next start (--persist)"
        )

    def _config(self, name: str) -> NodeConfig:
        config = node_config(self.plan, name, self.endpoint, domain=self.domain, log_level=self.log_level)
        return msgspec.structs.replace(config, credentials=self.logins.get(name))

    def _child(self, name: str) -> Child:
        """The Child for node ``name``: its command and environment, made once (its config
        changed by ``--persist``).  A built-in kind is forked by the zygote; a user's node class
        is always exec'd (``python -m turtlectl.runtime TARGET``): the zygote never imports a user's module
        (runtime/__main__.py says why); so is a ``cmd`` node's program."""
        if name in self.plan.commands:  # a user's program or node class runs in the launch file's folder
            argv, env = program_command(name, self.plan.commands[name], self.endpoint, self.domain)
            return Child(name, argv, env, self.printer, self.plan.folder)
        kind = self.plan.kinds[name]
        argv, env = node_command(self._config(name), supervisor_pid=os.getpid(), kind=kind)
        env[PROJECT_VAR] = self.plan.folder  # a built-in imports a user's module (a type it bridges) from there
        if self.zygote is not None and kind.builtin:
            return ZygoteChild(name, argv, env, self.printer, self.zygote)
        return Child(name, argv, env, self.printer, None if kind.builtin else self.plan.folder)
