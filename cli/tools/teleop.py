"""``turtlectl teleop``: drive the turtle from the keyboard, as turtlesim's
``teleop_turtle_key``.  The shell around cli.tools.keyboard (which decides what to send when): the
terminal in cbreak mode, a client session publishing ``turtle1/cmd_vel``, the pose for the
status line, and a cancel (reason "teleop") of a goal running when the keys start driving.

The terminal is restored on every way out: q, Ctrl-C, SIGTERM, SIGHUP (the terminal went
away: nothing more is written to it), the router lost with ``--exit-on-loss``; a stop command
goes out first whenever anything was being sent.  A lost router is otherwise waited for as
every long-running tool does (cli.tools.routerwatch), said on the status line: nothing is sent
meanwhile (a command queued for a router that is back later would drive on stale keys), and
driving resumes at the next key once it is back.
"""

from __future__ import annotations

import math
import os
import select
import signal
import termios
import threading
import time
import tty
from typing import TextIO

import zenoh

from turtlectl.cli.tools.keyboard import Driver, Shown, keys, status_line
from turtlectl.cli.tools.routerwatch import watch
from turtlectl.messages import Cancel, Pose, Twist, decode, encode, encoding_for
from turtlectl.messages.angles import heading_degrees
from turtlectl.messages.codec import type_name
from turtlectl.messages.keys import (
    CANCEL,
    CLIENT_ENTITY_TOKEN_PREFIX,
    CLIENT_NODE_TOKEN_PREFIX,
    CMD_VEL,
    FEEDBACK,
    POSE,
    EntityInfo,
    name_chunk,
    parse_client_node_token,
    parse_entity_token,
    resolve,
)
from turtlectl.runtime.client import presence
from turtlectl.runtime.client.errors import BadInput, CannotStart
from turtlectl.runtime.client.graph import NodeRow, clients_publishing, who
from turtlectl.runtime.client.session import ROUTER_CHECK, live_graph, require
from turtlectl.runtime.client.sigint import stop_on_signals

POLL = 0.02  # s: the longest a key waits to be read
LINE_PERIOD = 0.1  # s between redraws of the status line
GOAL_SEEN = 0.5  # s: feedback this recent means a goal is running
#: what the caller of a goal teleop cancels is told
TAKEN_OVER = "the keyboard took over (turtlectl teleop)"
NOT_A_TERMINAL = "teleop reads keys from a terminal, and its input is not one (run it in a terminal)"
HELP = "arrows or w/a/s/d drive (held: go, released: stop); space stops; q quits"


class _Goals:
    """Whether a goal is running (its feedback is recent), and a cancel of it, without waiting."""

    def __init__(self, session: zenoh.Session, namespace: str = ""):
        self.session = session
        self.last_feedback = -math.inf  # monotonic s
        self.canceled_at = -math.inf
        self.cancel_key = resolve(CANCEL, namespace)
        self._sub = presence.subscriber(session, resolve(FEEDBACK, namespace), self._on_feedback)

    def _on_feedback(self, _sample: zenoh.Sample) -> None:  # Zenoh thread: a time only
        self.last_feedback = time.monotonic()

    def running(self, now: float) -> bool:
        return now - self.last_feedback < GOAL_SEEN

    def cancel(self, now: float) -> None:
        """Cancel the running goal (reason "teleop"); the Ack is not waited for."""
        self.canceled_at = now
        self.session.get(
            self.cancel_key,
            lambda _reply: None,
            payload=encode(Cancel(reason="teleop", detail=TAKEN_OVER)),
            encoding=zenoh.Encoding(encoding_for(Cancel)),
            timeout=2.0,
        )

    def close(self) -> None:
        self._sub.undeclare()


class _Rivals:
    """Another client that starts publishing this teleop's ``cmd_vel`` (a teleop run with
    --force): ``warning`` names it, host included, asked on the teleop's own thread."""

    def __init__(self, session: zenoh.Session, cmd_vel: str, me: str):
        self.session, self.cmd_vel, self.me = session, cmd_vel, me
        self._new: list[EntityInfo] = []  # appended on Zenoh's thread, taken on the teleop's
        selector = f"{CLIENT_ENTITY_TOKEN_PREFIX}/*/*/pub/*/{cmd_vel}"
        self._sub = session.liveliness().declare_subscriber(selector, self._on_token)

    def _on_token(self, sample: zenoh.Sample) -> None:  # Zenoh thread
        entity = parse_entity_token(str(sample.key_expr), CLIENT_ENTITY_TOKEN_PREFIX)
        if sample.kind == zenoh.SampleKind.PUT and entity is not None and entity.node != self.me:
            self._new.append(entity)

    def warning(self) -> str:
        """A note naming a client that began to publish on cmd_vel since the last call, else ""."""
        if not self._new:
            return ""
        entity = self._new.pop()
        host = ""
        for reply in self.session.liveliness().get(
            f"{CLIENT_NODE_TOKEN_PREFIX}/{name_chunk(entity.node)}/**", timeout=1.0
        ):
            found = parse_client_node_token(str(reply.ok.key_expr)) if reply.ok is not None else None
            host = found.host if found is not None else host
        other = NodeRow(name=entity.node, pid=entity.pid, host=host, uptime=0.0)
        return f"warning: {who(other)} also drives {self.cmd_vel} (started with --force)"

    def close(self) -> None:
        self._sub.undeclare()


class _Teleop:
    """One teleop run: the session's publisher and subscribers, the driver, the terminal."""

    def __init__(
        self, session: zenoh.Session, driver: Driver, endpoint: str, fd: int, out: TextIO, namespace: str = ""
    ):
        self.session, self.driver, self.endpoint, self.fd, self.out = session, driver, endpoint, fd, out
        self.latest: Pose | None = None
        self.seq = 0
        self.hung_up = False
        self.note = ""
        cmd_vel = resolve(CMD_VEL, namespace)
        self.publisher = presence.publisher(session, cmd_vel, type_name(Twist), encoding_for(Twist))
        me = presence.of(session)
        self.rivals = _Rivals(session, cmd_vel, me.name if me else "")
        self.pose_sub = presence.subscriber(session, resolve(POSE, namespace), self._on_pose)
        self.goals = _Goals(session, namespace)

    def _on_pose(self, sample: zenoh.Sample) -> None:  # Zenoh thread: keep the newest valid pose
        try:
            self.latest = decode(sample.payload.to_bytes(), Pose)
        except ValueError:
            pass

    def send(self, twist: Twist) -> None:
        self.publisher.put(
            encode(Twist(linear=twist.linear, angular=twist.angular, stamp=time.time_ns(), seq=self.seq))
        )
        self.seq += 1

    def write(self, text: str) -> None:
        """Write to the terminal unless it has gone away."""
        if self.hung_up:
            return
        try:
            self.out.write(text)
            self.out.flush()
        except OSError:
            self.hung_up = True

    def drive(self, stop: threading.Event, exit_on_loss: bool = False) -> str:
        """Read keys and publish until told to stop; returns why it ended.  RouterLost
        (Unreachable) when the router is lost and ``exit_on_loss``."""
        next_line = next_check = 0.0
        router = watch(self.session, self.endpoint, "driving", exit_on_loss)
        while not stop.is_set():
            ready, _, _ = select.select([self.fd], [], [], POLL)
            now = time.monotonic()
            if ready:
                try:
                    data = os.read(self.fd, 64)
                except OSError:
                    data = b""
                if not data:  # the terminal went away
                    self.hung_up = True
                    return "the terminal went away"
                for key in keys(data):
                    if key == "quit":
                        return "quit"
                    if router.lost:
                        continue  # nothing is sent without a router
                    if self.driver.press(key, now) and self.goals.running(now):
                        self.cancel_goal(now)
                    elif key == "stop":  # space stops a goal's driving too, one just started included
                        self.goals.cancel(now)
                        if self.goals.running(now):
                            self.note = "canceled the running goal (reason teleop)"
            if (line := router.check(now)) is not None:
                self.note = line.split(" (")[0]
                self.driver.halt()  # lost: nothing more is sent; back: the next key drives
            if router.lost:
                if now >= next_line:
                    next_line = now + LINE_PERIOD
                    self.write("\r\x1b[K" + status_line(self.shown(), self.width()))
                continue
            goals = self.goals
            if self.driver.sending and goals.last_feedback > goals.canceled_at + 0.2 and goals.running(now):
                self.cancel_goal(now)  # a goal started while the keys drive
            command = self.driver.tick(now)
            if command is not None:
                self.send(command)
            if now >= next_check:  # another client started driving this turtle (--force): say so
                next_check = now + ROUTER_CHECK
                warning = self.rivals.warning()
                if warning:
                    self.note = warning.removeprefix("warning: ")
            if now >= next_line:
                next_line = now + LINE_PERIOD
                self.write("\r\x1b[K" + status_line(self.shown(), self.width()))
        return "the terminal went away" if self.hung_up else "stopped"

    def cancel_goal(self, now: float) -> None:
        self.goals.cancel(now)
        self.note = "canceled the running goal (reason teleop)"

    def width(self) -> int:
        """The terminal's width now (it may be resized), 80 if it cannot tell."""
        try:
            return os.get_terminal_size(self.fd).columns or 80
        except OSError:
            return 80

    def shown(self) -> Shown:
        pose = self.latest
        where = None if pose is None else (pose.x, pose.y, heading_degrees(pose.theta))
        return Shown(command=self.driver.command, pose=where, note=self.note)

    def close(self) -> None:
        """A stop command if anything was sent, then the session's entities undeclared."""
        last = self.driver.halt()
        if last is not None:
            self.send(last)
        self.goals.close()
        self.rivals.close()
        self.pose_sub.undeclare()
        self.publisher.undeclare()


def terminal_fd(stream: TextIO) -> int:
    """The file descriptor of ``stream`` if it is a terminal, else BadInput (checked before
    anything is opened)."""
    try:
        fd = stream.fileno()
    except (OSError, ValueError):  # io.UnsupportedOperation is both: no file under it
        fd = -1
    if fd < 0 or not os.isatty(fd):
        raise BadInput(NOT_A_TERMINAL)
    return fd


def others_driving(session: zenoh.Session, cmd_vel: str, force: bool) -> str:
    """A warning naming the other clients that publish ``cmd_vel`` ("" if none); without
    ``force``, CannotStart (exit 4) naming them instead: two teleops on one turtle both drive it."""
    others = clients_publishing(live_graph(session), cmd_vel)
    if not others:
        return ""
    names = ", ".join(who(o) for o in others)
    if not force:
        raise CannotStart(
            f"{cmd_vel} is already driven by {names}: two drivers would both steer the turtle; "
            "quit that one, or add --force to drive it too"
        )
    return f"warning: {cmd_vel} is also driven by {names} (--force: both drive the turtle)"


def run_teleop(
    session: zenoh.Session,
    linear: float,
    angular: float,
    endpoint: str,
    fd: int,
    out: TextIO,
    namespace: str = "",
    force: bool = False,
    exit_on_loss: bool = False,
) -> str:
    """Drive until q, Ctrl-C, SIGTERM or SIGHUP; returns why it ended.  Raises BadInput if
    ``fd`` is not a terminal, RouterLost (Unreachable) if the router goes away and
    ``exit_on_loss``, CannotStart if another client drives the turtle already, unless ``force``
    (then both are warned).  ``namespace``: the turtle's nodes' (``turtle2`` drives
    turtle2/cmd_vel; "" turtle1)."""
    if not os.isatty(fd):
        raise BadInput(NOT_A_TERMINAL)
    cmd_vel = resolve(CMD_VEL, namespace)
    require(session, "publish", cmd_vel)
    warning = others_driving(session, cmd_vel, force)
    teleop = _Teleop(session, Driver(linear, angular), endpoint, fd, out, namespace)
    teleop.note = warning.removeprefix("warning: ")
    terminal = termios.tcgetattr(fd)
    try:
        tty.setcbreak(fd)  # keys as they are typed, no echo; Ctrl-C still a signal
        teleop.write((warning + "\n" if warning else "") + HELP + "\n")
        with stop_on_signals(also=(signal.SIGHUP,)) as stop:
            # SIGHUP: the terminal is gone; nothing more is written to it
            signal.signal(signal.SIGHUP, lambda *_: (setattr(teleop, "hung_up", True), stop.set()))
            return teleop.drive(stop, exit_on_loss)
    finally:
        teleop.close()
        teleop.write("\r\x1b[K" + status_line(teleop.shown(), teleop.width()))  # the last word: stopped
        if not teleop.hung_up:
            try:
                termios.tcsetattr(fd, termios.TCSADRAIN, terminal)
            except termios.error:
                pass
        teleop.write("\n")
