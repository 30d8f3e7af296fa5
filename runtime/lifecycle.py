"""A node process from start to exit: config, signals, parent death, router watch,
the node's spin, and a bounded close.

``run_main(node_class, params_type)`` is what a node module calls; ``run`` does the
work and returns the exit code, and ``run_main`` is the one place that exits:

* 0 stopped by a signal or because the supervisor went away (a SIGTERM that comes before the
  node has claimed what it owns ends it at once instead: killed by SIGTERM, nothing to save);
* 1 the node's own code raised (traceback logged once, shutdown hooks run, so the
  navigator still commands a stop; the supervisor's respawn applies);
* 2 the configuration could not be used (the node's class raised BadInput while starting, one line),
  or the node declared something its interface does not name (runtime.interface); 3 no Zenoh
  session; 4 another node already holds what this one claims (see ``Node.claim``), or the node's
  class raised CannotStart (something it needs is missing): the supervisor does not respawn
  a node after a 2 or a 4, the next start would end the same way.

The numbers are the one table of every turtlectl process, ``runtime.exitcodes.ExitCode``.
"""

from __future__ import annotations

import ctypes
import logging
import os
import signal
import socket
import sys
import time
from collections.abc import Callable
from typing import Any, NoReturn

import msgspec
import zenoh

from turtlectl.messages.codec import TypeClash
from turtlectl.messages.keys import NodeInfo, node_token
from turtlectl.runtime import log_stream
from turtlectl.runtime.client.errors import BadInput, CannotStart
from turtlectl.runtime.config import ENV_VAR, SUPERVISOR_PID_VAR, decode_config
from turtlectl.runtime.exitcodes import ExitCode
from turtlectl.runtime.interface import OutsideInterface, where
from turtlectl.runtime.node import Node, P
from turtlectl.runtime.session import close_session, node_session_config, open_session

_PR_SET_PDEATHSIG = 1
_PARENT_CHECK_PERIOD = 0.5  # s
_ROUTER_CHECK_PERIOD = 1.0  # s
_ROUTER_WAIT = 0.25  # s a new session may take to reach the router before the node starts anyway


def _router_watch(node: Node[Any], endpoint: str) -> Callable[[], None]:
    """A check that reports, once each way, losing and finding again the router: the node
    keeps running meanwhile (Zenoh reconnects by itself) and says so."""
    connected = [bool(node.session.info.routers_zid())]  # as the session opened
    if not connected[0]:
        node.log.warning("no router at %s yet; running, and trying to reach it", endpoint)

    def check() -> None:
        now = bool(node.session.info.routers_zid())
        if now != connected[0]:
            connected[0] = now
            if now:
                node.log.info("router at %s is reached", endpoint)
            else:
                node.log.warning("lost the router at %s; still running, reconnecting", endpoint)

    return check


def _await_router(session: zenoh.Session, timeout: float) -> None:
    """Give the session up to ``timeout`` s to reach the router: it opens without waiting
    (scouting/delay 0), the router is usually reached within a few ms, and the router watch
    then starts from what is true (connected, or not yet)."""
    deadline = time.monotonic() + timeout
    while not session.info.routers_zid() and time.monotonic() < deadline:
        time.sleep(0.002)  # pacing: polling the session's connection state under a deadline


def _watch_parent() -> Callable[[], bool]:
    """Die with the supervisor: ask Linux for SIGTERM when the parent dies, and
    return a check that reports a changed parent (the fallback on other systems)."""
    expected = os.environ.get(SUPERVISOR_PID_VAR)
    if not expected or not expected.isdigit():
        return lambda: False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
    except (OSError, AttributeError):
        pass
    parent = int(expected)
    return lambda: os.getppid() != parent


class _Closed:
    """Whether the session closed within its bound (if not, ``main`` must not wait for Zenoh's
    threads at interpreter exit)."""

    clean = True


def run(node_class: Callable[[Node[P]], Any], params_type: type[P]) -> int:
    """Run one node in this process: read the config, open the session, build the node,
    spin, run its shutdown hooks, close.  Returns the exit code (see the module docstring)."""
    started = time.time_ns()
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(message)s", stream=sys.stderr)
    log = logging.getLogger("runtime")
    early_stop: list[int] = []  # a Ctrl-C before the node exists is kept, not lost (nor a traceback)
    signal.signal(signal.SIGINT, lambda signum, _frame: early_stop.append(signum))
    # until the node has claimed what it owns, a SIGTERM (the supervisor's death included) ends it
    # at once: it has nothing to save yet, and a claim may wait up to 1 s for a router now gone
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    parent_gone = _watch_parent()
    if parent_gone():
        return ExitCode.OK
    try:
        config = decode_config(os.environ[ENV_VAR])
        params = msgspec.convert(config.params, params_type, strict=True)
        logging.getLogger().setLevel(config.log_level)
    except KeyError:
        log.error("%s is not set: start nodes with `turtlectl launch` or `turtlectl run`", ENV_VAR)
        return ExitCode.BAD_INPUT
    except (msgspec.ValidationError, msgspec.DecodeError) as exc:
        log.error("invalid node configuration: %s", exc)
        return ExitCode.BAD_INPUT

    try:
        session = open_session(node_session_config(config.connect, config.domain, config.credentials))
    except zenoh.ZError as exc:
        log.error("cannot open a Zenoh session to %s: %s", config.connect, exc)
        return ExitCode.UNREACHABLE
    except ValueError as exc:  # a bad TURTLECTL_PEER_TIMEOUT (runtime.endpoint.peer_timeout)
        log.error("%s", exc)
        return ExitCode.BAD_INPUT

    _await_router(session, _ROUTER_WAIT)
    stream: log_stream.LogStream | None = None
    try:
        if early_stop or parent_gone():  # stopped while starting (the supervisor died): build nothing
            return ExitCode.OK
        node = Node(config, params, session, started)
        stream = log_stream.start(node)  # every record from here on also on turtlectl/log/<node> (runtime.log_stream)
        signal.signal(signal.SIGINT, node.stop)
        node.timer(_PARENT_CHECK_PERIOD, lambda: parent_gone() and node.stop())
        node.timer(_ROUTER_CHECK_PERIOD, _router_watch(node, config.connect))
        if early_stop:
            node.stop()
        try:
            for claim in config.claims:
                node.claim(claim)
            signal.signal(signal.SIGTERM, node.stop)
            if node.stopping:  # stopped while it claimed: build nothing
                node.shutdown()
                return ExitCode.OK
            node_class(node)
        except CannotStart as exc:  # another node holds its claim (NodeConflict), something it needs is missing
            log.error("%s", exc)
            node.shutdown()
            return ExitCode.CANNOT_START
        except TypeClash as exc:  # two classes under one type name: starting again cannot help
            node.log.error('%s (give one of them another name or package: tag="package/Name")', exc)
            node.shutdown()
            return ExitCode.BAD_INPUT
        except OutsideInterface as exc:  # its declaration and its code disagree: starting again cannot help
            at = where(exc)
            node.log.error("%s%s", exc, f" ({at})" if at else "")
            node.shutdown()
            return ExitCode.BAD_INPUT
        except BadInput as exc:  # its configuration cannot be used (one line says why): starting again cannot help
            node.log.error("%s", exc)
            node.shutdown()
            return ExitCode.BAD_INPUT
        except Exception:  # the node's own code: a defect, reported once, and the node still stops cleanly
            node.log.exception("failed while starting")
            node.shutdown()
            return ExitCode.FAILED
        me = NodeInfo(name=config.name, pid=os.getpid(), host=socket.gethostname(), start_ns=started)
        token = session.liveliness().declare_token(node_token(me))
        node.log.info("ready (pid %d)", os.getpid())
        ok = node.spin()
        token.undeclare()
        node.log.info("stopped" if ok else "stopped after an error")
        return ExitCode.OK if ok else ExitCode.FAILED
    finally:
        if stream is not None:
            stream.close()
        if not close_session(session):
            log.warning("Zenoh session did not close within 2 s; exiting anyway")
            _Closed.clean = False


def run_main(node_class: Callable[[Node[P]], Any], params_type: type[P]) -> NoReturn:
    """Entry point of a node module (``run_main(MyNode, MyParams)``):
    the one place a node process exits."""
    code = run(node_class, params_type)
    logging.shutdown()
    if not _Closed.clean:
        os._exit(code)  # Zenoh's threads did not stop: do not wait for them at exit
    sys.exit(code)
