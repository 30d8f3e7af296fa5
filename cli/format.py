"""Text for people and for programs: how messages and outcomes are printed (pure)."""

from __future__ import annotations

import math

from messages import Ack, Message, NavigateToFeedback, NavigateToResponse, to_builtins, to_json


def _value(value: object, indent: str) -> str:
    if isinstance(value, float):
        return "inf" if math.isinf(value) and value > 0 else f"{value:.6g}"
    if isinstance(value, list):
        if all(isinstance(v, (int, float)) for v in value):
            return "[" + ", ".join(_value(v, indent) for v in value) + "]"
        return "\n" + "\n".join(f"{indent}- {_value(v, indent + '  ')}" for v in value)
    if isinstance(value, dict):
        return "\n" + "\n".join(f"{indent}  {k}: {_value(v, indent + '  ')}" for k, v in value.items())
    return str(value)


def message_block(msg: Message) -> str:
    """A readable block, as ``ros2 topic echo`` prints: one ``field: value`` per line, then ``---``."""
    data = to_builtins(msg)
    lines = [f"{key}: {_value(value, '')}" for key, value in data.items()]
    return "\n".join(lines) + "\n---"


def message_json(msg: Message) -> str:
    """One JSON object on one line (its ``type`` names the message type)."""
    return to_json(msg).decode()


def outcome_line(response: NavigateToResponse) -> str:
    """One line for people: what happened to a goal."""
    where = f"at ({response.x:.3f}, {response.y:.3f}, {response.theta:.1f} deg)"
    errors = f"error {response.position_error:.4f} m, {response.heading_error:.2f} deg"
    if response.success:
        return f"reached {where} in {response.time_taken:.3f} s ({errors})"
    if response.refused:
        return f"refused: {response.reason}"
    return f"not reached: {response.reason} after {response.time_taken:.3f} s; {where}, {errors}"


def progress_line(fb: NavigateToFeedback) -> str:
    """One short line for the live progress of a goal (rewritten in place on a terminal)."""
    return (
        f"{fb.state:8s} {fb.distance_remaining:6.3f} m, {fb.heading_remaining:5.1f} deg to go, "
        f"eta {fb.eta:4.1f} s | at ({fb.x:.2f}, {fb.y:.2f}, {fb.theta:.0f} deg) | {fb.elapsed:.1f} s"
    )


def ack_lines(acks: list[Ack]) -> str:
    return "\n".join(a.detail for a in acks)
