"""The command line's goal client: one goal sent to one goal service (runtime.goals' wire), the
same way for ``goto``, ``Client.goto``, ``Client.send_goal``, ``action send-goal`` and ``call
navigate_to``.  Nothing here prints; functions return data or raise a TurtlectlError.

What every goal sent from here gets: a caller token held while it waits (named in the goal's
``client`` field when its type has one, else in the query's attachment), so its server ends the
goal when the caller goes away; its feedback handed on as it arrives; its result told apart by
its type; and a goal given up on (a timeout, Ctrl-C) canceled through ``KEY/cancel`` with the
answer checked (none within CANCEL_WAIT s: exit code 5, the goal may still run).  Messages name
the server as its user knows it: "the navigator" for ``navigate_to``, else "the goal service
KEY" and the nodes serving it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import msgspec
import zenoh

from turtlectl.messages import Ack, Cancel, Message, NavigateToResponse
from turtlectl.messages.codec import type_name
from turtlectl.messages.keys import NAVIGATE_TO
from turtlectl.runtime.client.errors import CancelUnconfirmed, Failed, GoalCanceled, Interrupted, TurtlectlError
from turtlectl.runtime.client.services import (
    ROUTER_LOSS_WAIT,
    NoAnswer,
    Raw,
    RouterLost,
    replies,
    router_lost_soon,
)
from turtlectl.runtime.client.session import caller_token
from turtlectl.runtime.client.sigint import sigint_deferred
from turtlectl.runtime.goal_reasons import CANCELED

__all__ = [
    "API_LIMIT",
    "CANCEL_WAIT",
    "CLI_LIMIT",
    "NO_LIMIT",
    "GoalService",
    "cancel_goal",
    "canceled",
    "given_up",
    "navigate_to",
    "run_goal",
]

NO_LIMIT = 24 * 3600.0  # s: wait as long as the server lets the goal run (its own timeout decides)
CANCEL_WAIT = 2.0  # s for KEY/cancel to confirm the cancel of a goal given up on
API_LIMIT = "timeout={:g} s"  # a timeout as the Python client (turtlectl.Client) names it
CLI_LIMIT = "--timeout {:g} s"  # as the command line names it


class GoalService(msgspec.Struct, frozen=True):
    """A goal service as a client sends to it: ``key`` (as sent: with the domain from outside
    it, in the turtle's namespace) and ``result``, its result type's name (codec.type_name, as
    the graph lists it): the reply that ends a goal."""

    key: str
    result: str
    servers: tuple[str, ...] = ()  # the nodes serving it, when known (the graph's)

    @property
    def is_navigate_to(self) -> bool:
        """A navigator's ``navigate_to`` (any turtle's, any domain's): its own words apply."""
        return self.key.rsplit("/", 1)[-1] == NAVIGATE_TO

    @property
    def server(self) -> str:
        """Who serves it, as its messages name it."""
        if self.is_navigate_to:
            return "the navigator"
        nodes = f" ({', '.join(self.servers)})" if self.servers else ""
        return f"the goal service {self.key}{nodes}"

    @property
    def cancel_key(self) -> str:
        return f"{self.key}/cancel"

    def is_result(self, message: Message | Raw) -> bool:
        return isinstance(message, Message) and type_name(type(message)) == self.result


def navigate_to(key: str = NAVIGATE_TO) -> GoalService:
    """A navigator's goal service (``navigate_to``, ``turtle2/navigate_to``, ...)."""
    return GoalService(key, type_name(NavigateToResponse))


def cancel_goal(session: zenoh.Session, service: GoalService) -> Ack | str:
    """Ask ``KEY/cancel`` to end the running goal: its Ack, or why nobody confirmed it within
    CANCEL_WAIT s (nothing serves it, an error, silence)."""
    try:
        for reply in replies(session, service.cancel_key, Cancel(), CANCEL_WAIT, goal=True):
            if isinstance(reply, Ack):
                return reply
    except TurtlectlError as exc:
        return exc.said  # its advice is not for this line
    return f"{service.cancel_key} sent no Ack"


def given_up(
    why: str,
    answer: Ack | str,
    interrupted: bool,
    service: GoalService | None = None,
    *,
    response: Any = None,
    feedback: Any = None,
    timeout: float | None = None,
) -> TurtlectlError:
    """The error for a goal given up on (``why``: a timeout, or "interrupted" by Ctrl-C), given
    the cancel's ``answer`` (an Ack, or why nobody confirmed it) and the ``service`` (default:
    ``navigate_to``).  Confirmed: GoalCanceled (exit 1, a goal not reached: with the server's
    ``response`` and the caller's ``timeout``) or Interrupted (130); a server that had no goal
    running any more confirms too.  Unconfirmed: CancelUnconfirmed (exit 5): the goal may still
    run (the turtle may still drive).  Each carries the goal's last ``feedback``."""
    service = service or navigate_to()
    lead = f"{why}: " if interrupted else f"{why}; "
    error: TurtlectlError
    if isinstance(answer, str):
        if service.is_navigate_to:
            still, again = "the turtle may still be driving to the goal", "`turtlectl cancel` asks again"
        else:
            still, again = "the goal may still be running", f"`turtlectl call {service.cancel_key}` asks again"
        error = CancelUnconfirmed(f"{lead}nobody confirmed the cancel: {still} ({answer}; {again})")
        error.feedback = feedback
        return error
    who = service.server
    said = f"{who} canceled the goal" if answer.ok else f"the goal had ended meanwhile ({who}: {answer.detail})"
    if interrupted:
        error = Interrupted(lead + said)
        error.feedback = feedback
        return error
    return GoalCanceled(lead + said, response, feedback, timeout, said)


def canceled(service: GoalService, response: Any, feedback: Any = None) -> GoalCanceled:
    """A goal ended by a cancel from anyone (its result's ``reason`` "canceled"), as the Python
    client raises it: the same error as its own timeout's, with the server's ``response``."""
    detail = getattr(response, "detail", "")
    said = f"{service.server} canceled the goal"
    return GoalCanceled(said + (f": {detail}" if detail else ""), response, feedback, None, said)


def run_goal(
    session: zenoh.Session,
    service: GoalService,
    goal: Message,
    timeout: float,
    on_feedback: Callable[[Any], None] | None = None,
    limit: str = API_LIMIT,
) -> Any:
    """Send ``goal`` to ``service`` and wait for its result, handing each feedback to
    ``on_feedback`` as it arrives, while holding a caller token (released when this ends,
    however it ends: the server then ends a goal still running).

    A goal given up on before its result (``timeout`` s, or Ctrl-C anywhere in here,
    ``on_feedback`` included) is canceled through ``KEY/cancel`` and the answer checked
    (``given_up``): after a timeout the server's result that follows its confirmed cancel is
    awaited (CANCEL_WAIT s), so that GoalCanceled carries the final pose.  ``limit``: how the
    timeout is named to its user (``timeout={:g} s``, the command line's ``--timeout {:g} s``).
    Raises Failed if the server stops answering; RouterLost if the router goes away."""
    last: Any = None  # the goal's last feedback
    with caller_token(session, service.key) as client_id:
        request = goal
        if "client" in type(goal).__struct_fields__ and not getattr(goal, "client", ""):
            request = msgspec.structs.replace(goal, client=client_id)  # type: ignore[call-arg]
        deadline = time.monotonic() + timeout
        answered = False
        why, answer, result_by = "", None, 0.0  # once given up on: why, the cancel's Ack, how long for the result
        waited = timeout + 3 * CANCEL_WAIT  # the query outlives the timeout: the result after the cancel
        try:
            for message in replies(
                session, service.key, request, waited, attachment=client_id.encode(), goal=True, idle=True
            ):
                now = time.monotonic()
                if message is not None and service.is_result(message):
                    if answer is not None and getattr(message, "reason", "") == CANCELED:
                        raise given_up(why, answer, False, service, response=message, feedback=last, timeout=timeout)
                    return message  # reached, or ended otherwise before the cancel was served
                if message is not None:
                    answered = True
                    last = message
                    if on_feedback is not None:
                        on_feedback(message)
                if answer is None and now >= deadline:
                    if answered:
                        why = f"the goal did not end within {limit.format(timeout)}"
                    else:
                        why = f"{service.key} did not answer within {limit.format(timeout)}"
                    with sigint_deferred():  # bounded (CANCEL_WAIT): a Ctrl-C must not skip the check
                        answer = cancel_goal(session, service)
                    if isinstance(answer, str):
                        raise given_up(why, answer, False, service, feedback=last)
                    result_by = time.monotonic() + CANCEL_WAIT
                elif answer is not None and now >= result_by:
                    raise given_up(why, answer, False, service, feedback=last, timeout=timeout)
        except NoAnswer:  # the query's own limit, beyond the timeout and the cancel: seldom reached
            if answer is None:
                why = f"the goal did not end within {limit.format(timeout)}"
                with sigint_deferred():
                    answer = cancel_goal(session, service)
            raise given_up(why, answer, False, service, feedback=last, timeout=timeout) from None
        except KeyboardInterrupt:
            with sigint_deferred():
                answer = cancel_goal(session, service)
            raise given_up("interrupted", answer, True, service, feedback=last) from None
        except RouterLost:
            raise RouterLost(during="before the goal ended") from None
        if router_lost_soon(session, lasted=ROUTER_LOSS_WAIT):  # the replies ended without a result: why?
            raise RouterLost(during="before the goal ended")
    if answer is not None:  # canceled, and the server's replies ended without its result
        raise given_up(why, answer, False, service, feedback=last, timeout=timeout)
    raise Failed(f"{service.server} stopped answering before the goal ended (did it exit?)")
