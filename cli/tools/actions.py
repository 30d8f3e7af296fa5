"""Goal services from the command line, as ``ros2 action``: list them with their types, and
send a goal to any of them (runtime.goals' wire).  Nothing here prints."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from turtlectl.cli.tools import build
from turtlectl.cli.tools.topics import graph
from turtlectl.messages import Message
from turtlectl.runtime.client import goals
from turtlectl.runtime.client.errors import GoalCanceled, Unreachable
from turtlectl.runtime.client.graph import GoalRow
from turtlectl.runtime.client.session import check_key


def goal_services(connect: str, domain: str) -> list[GoalRow]:
    """Every goal service running now, by key."""
    return graph(connect, domain).goals


def goal_service(connect: str, domain: str, key: str) -> GoalRow:
    """The goal service ``key``; Unreachable naming those that run when it does not."""
    key = check_key(key)
    rows = goal_services(connect, domain)
    for row in rows:
        if row.key == key:
            return row
    running = ", ".join(r.key for r in rows) or "none"
    raise Unreachable(f"no goal service {key} is running (running: {running})")


def rows_text(rows: list[GoalRow]) -> str:
    """One line per goal service: its key, its three types and who serves it."""
    if not rows:
        return "no goal services"
    width = max(len(r.key) for r in rows)
    return "\n".join(
        f"{r.key.ljust(width)}  [{r.goal} -> {r.feedback} -> {r.result}]  served by {', '.join(r.servers) or 'nobody'}"
        for r in rows
    )


def row_text(row: GoalRow) -> str:
    """``action info``: the key, who serves it, its types."""
    return "\n".join(
        [
            f"Goal service: {row.key}",
            f"Servers: {', '.join(row.servers)}",
            f"Goal: {row.goal}",
            f"Feedback: {row.feedback}",
            f"Result: {row.result}",
            f"Cancel: {row.key}/cancel (Cancel -> Ack); feedback for observers: {row.key}/feedback",
        ]
    )


def send_goal(
    connect: str,
    domain: str,
    key: str,
    text: str,
    timeout: float | None,
    on_feedback: Callable[[Any], None] | None,
) -> Message:
    """Send the goal ``text`` (JSON) to the goal service ``key`` and wait for its result, feedback
    handed to ``on_feedback`` (``Client.run_goal``: a --timeout or Ctrl-C cancels it and checks
    the Ack); a result canceled by anyone else is returned, as any other result."""
    from turtlectl.runtime.client.api import Client

    key = check_key(key)
    build.json_text(text)  # bad JSON is said before any system is asked
    with Client(connect, domain, timeout_named=goals.CLI_LIMIT) as client:
        row = client.goal_service(key)  # its types learnt from the nodes (a user's, as they describe them)
        goal = build.message_from_json(text, build.type_named(row.goal))
        try:
            return client.run_goal(key, goal, on_feedback, timeout=timeout)
        except GoalCanceled as canceled:
            if canceled.timeout is not None or canceled.response is None:  # --timeout's: an error
                raise
            return canceled.response  # type: ignore[no-any-return]
