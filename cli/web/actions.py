"""What a page asks the system to do, done as the command line does it, through one ``Client``:
``goal`` is ``turtlectl goto --turtle``, ``teleport``/``spawn``/``kill`` are those commands,
``set_param`` is ``turtlectl param set`` (its checks and its messages), ``drive`` is what
``turtlectl teleop`` publishes.  Each request runs on a worker thread (a goal for as long as it
runs) and answers with the text the command would print, or its error line.

Teleop's safety, kept by the server (``Deadman``): a turtle a page drives is stopped when the page
says so (a key released, the page hidden), when its drive commands stop coming for
DRIVE_DEADMAN s (a frozen page, a lost network), and when its connection closes.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

import msgspec

from turtlectl.cli.tools.format import ack_lines, teleport_line
from turtlectl.cli.web import protocol
from turtlectl.cli.web.protocol import CancelGoal, Drive, Goal, Kill, Params, SetParam, Spawn, Stop, Teleport
from turtlectl.messages import Ack, NavigateToFeedback, NavigateToRequest, SpawnResponse, TeleportAbsolute, Twist
from turtlectl.messages import Kill as KillRequest
from turtlectl.messages.angles import heading_radians
from turtlectl.messages.keys import KILL, NAVIGATE_TO, SPAWN, cmd_vel_key, resolve, teleport_key
from turtlectl.runtime.client.api import Client
from turtlectl.runtime.client.errors import TurtlectlError
from turtlectl.runtime.client.session import live_turtle_namespace

TAKEN_OVER = "the keyboard took over (turtlectl web)"
Send = Callable[[bytes], None]  # a frame to one page, from any thread


class Deadman:
    """The turtles one page drives, and when each last got a drive command (monotonic s): pure,
    on a clock the caller gives.  ``due(now)`` lists the turtles to stop now."""

    def __init__(self, limit: float = protocol.DRIVE_DEADMAN):
        self.limit = limit
        self.driving: dict[str, float] = {}

    def drive(self, turtle: str, now: float) -> bool:
        """A drive command for ``turtle``; True when it starts driving (it was at rest)."""
        started = turtle not in self.driving
        self.driving[turtle] = now
        return started

    def stop(self, turtle: str) -> bool:
        """The page stopped ``turtle``; True if it was driving."""
        return self.driving.pop(turtle, None) is not None

    def due(self, now: float) -> list[str]:
        """The turtles whose drive commands stopped ``limit`` s ago (no longer driving after)."""
        late = [t for t, last in self.driving.items() if now - last >= self.limit]
        for turtle in late:
            del self.driving[turtle]
        return late

    def all(self) -> list[str]:
        """Every turtle still driving (no longer after): the page went away."""
        turtles = list(self.driving)
        self.driving.clear()
        return turtles


class Actions:
    """The requests of every page, on ``client``; ``outcome`` gets a finished goal's frame (for
    every page); ``running(turtle)`` says whether a goal of the turtle runs now."""

    def __init__(self, client: Client, outcome: Send, running: Callable[[str], bool]):
        self.client = client
        self._outcome = outcome
        self._running = running
        self._namespaces: dict[str, str] = {}

    def namespace(self, turtle: str) -> str:
        """The namespace ``turtle``'s nodes run in (asked once per turtle)."""
        if turtle not in self._namespaces:
            self._namespaces[turtle] = live_turtle_namespace(self.client.session, turtle)
        return self._namespaces[turtle]

    def handle(self, frame: protocol.Inbound, send: Send) -> None:
        """Do ``frame``'s request on a worker thread; its reply goes to ``send``."""
        if isinstance(frame, Drive):  # a publish: at once, on the caller's thread
            self.drive(frame.turtle, frame.linear, frame.angular)
            return
        if isinstance(frame, Stop):
            self.drive(frame.turtle, 0.0, 0.0)
            return
        work = {
            Goal: self.goal,
            CancelGoal: self.cancel,
            Teleport: self.teleport,
            Spawn: self.spawn,
            Kill: self.kill,
            Params: self.params,
            SetParam: self.set_param,
        }.get(type(frame))
        if work is None:
            return

        def run() -> None:
            try:
                text, data = work(frame)  # type: ignore[operator]
                send(protocol.reply(frame, True, text, data))  # type: ignore[arg-type]
            except TurtlectlError as exc:
                send(protocol.reply(frame, False, str(exc)))  # type: ignore[arg-type]
            except Exception as exc:  # a request must never end the page's server
                send(protocol.reply(frame, False, f"{type(exc).__name__}: {exc}"))  # type: ignore[arg-type]

        threading.Thread(target=run, name=f"web {type(frame).__name__}", daemon=True).start()

    # driving ------------------------------------------------------------------------------------

    def drive(self, turtle: str, linear: float, angular: float) -> None:
        """Publish ``turtle``'s cmd_vel (m/s, rad/s), as teleop does."""
        self.client.publish(cmd_vel_key(turtle), Twist(linear=linear, angular=angular))

    def take_over(self, turtle: str) -> None:
        """The keys start driving ``turtle``: its running goal is canceled first, as teleop cancels it."""
        if self._running(turtle):
            key = resolve(NAVIGATE_TO, self.namespace(turtle))
            threading.Thread(target=self._cancel_quietly, args=(key,), daemon=True).start()

    def _cancel_quietly(self, key: str) -> None:
        try:
            self.client.cancel(key, "teleop", TAKEN_OVER)  # as turtlectl teleop's cancel
        except TurtlectlError:
            pass  # the goal ended meanwhile, or its navigator went: nothing left to cancel

    # requests ------------------------------------------------------------------------------------

    def goal(self, frame: Goal) -> tuple[str, Any]:
        key = resolve(NAVIGATE_TO, self.namespace(frame.turtle))
        request = NavigateToRequest(x=frame.x, y=frame.y, theta=frame.theta)
        started = time.monotonic()
        try:
            result = self.client.run_goal(key, request, _ignore)
        except TurtlectlError as exc:
            response = getattr(exc, "response", None)
            self._outcome(_outcome(frame.turtle, response, str(exc), time.monotonic() - started))
            raise
        self._outcome(_outcome(frame.turtle, result, getattr(result, "detail", ""), time.monotonic() - started))
        if getattr(result, "success", False):
            return f"{frame.turtle} reached ({frame.x:.2f}, {frame.y:.2f}) in {result.time_taken:.1f} s", None
        raise _Refused(f"{frame.turtle}: {getattr(result, 'reason', '')}: {getattr(result, 'detail', '')}")

    def cancel(self, frame: CancelGoal) -> tuple[str, Any]:
        ack = self.client.cancel(resolve(NAVIGATE_TO, self.namespace(frame.turtle)))
        if not ack.ok:
            raise _Refused(f"{frame.turtle}: no goal was running")
        return f"{frame.turtle}: goal canceled", None

    def teleport(self, frame: Teleport) -> tuple[str, Any]:
        request = TeleportAbsolute(x=frame.x, y=frame.y, theta=heading_radians(frame.theta))
        acks = [a for a in self.client.call_all(teleport_key(frame.turtle), request) if isinstance(a, Ack)]
        if not acks:
            raise _Refused("the simulator did not confirm the teleport")
        if not all(a.ok for a in acks):  # the simulator's own words, as teleport says them
            raise _Refused(ack_lines(acks))
        return f"{frame.turtle} {teleport_line(frame.x, frame.y, frame.theta)}", None

    def spawn(self, frame: Spawn) -> tuple[str, Any]:
        from turtlectl.messages import SpawnRequest

        request = SpawnRequest(x=frame.x, y=frame.y, theta=heading_radians(frame.theta), name=frame.name)
        names = [m.name for m in self.client.call_all(SPAWN, request) if isinstance(m, SpawnResponse)]
        if not names:
            raise _Refused("the simulator did not confirm the spawn")
        return f"spawned {names[-1]}", {"name": names[-1]}

    def kill(self, frame: Kill) -> tuple[str, Any]:
        acks = [a for a in self.client.call_all(KILL, KillRequest(name=frame.turtle)) if isinstance(a, Ack)]
        if not acks or not acks[-1].ok:
            raise _Refused(acks[-1].detail if acks else "the simulator did not confirm the kill")
        return acks[-1].detail or f"killed {frame.turtle}", None

    def params(self, frame: Params) -> tuple[str, Any]:
        """The node's parameters as ``param describe`` gives them: name, type, unit, range, default,
        meaning, whether it can change at run time (and why not), value."""
        from turtlectl.cli.tools.params import description

        described = description(self.client.connect, self.client.domain, frame.node)
        return f"{frame.node}: {len(described.parameters)} parameters", {
            "node": frame.node,
            "kind": described.kind,
            "parameters": msgspec.to_builtins(described.parameters),
        }

    def set_param(self, frame: SetParam) -> tuple[str, Any]:
        """``turtlectl param set NODE NAME VALUE``: the same checks, the node's answer or refusal."""
        from turtlectl.cli.tools.params import set_value

        return set_value(self.client.connect, self.client.domain, frame.node, frame.name, frame.value), None


class _Refused(TurtlectlError):
    """What the system refused, in its own words (a reply with ok false)."""


def _ignore(_feedback: NavigateToFeedback) -> None:
    """Feedback reaches every page from the published ``navigate_to/feedback``, not from here."""


def _outcome(turtle: str, response: Any, error: str, waited: float) -> bytes:
    """The ``outcome`` frame of a goal of ``turtle``: the navigator's response (None: none came)."""
    fields = msgspec.to_builtins(response) if response is not None else {}
    fields.pop("type", None)
    return protocol.encode(
        "outcome",
        turtle=turtle,
        success=bool(fields.get("success", False)),
        reason=fields.get("reason", "") or ("" if fields.get("success") else "error"),
        time_taken=fields.get("time_taken", waited),
        position_error=fields.get("position_error"),
        heading_error=fields.get("heading_error"),
        detail="" if fields.get("success") else (fields.get("detail") or error),
    )
