"""The verdicts of ``turtlectl verify`` as one table for people, or one JSON object (pure)."""

from __future__ import annotations

import msgspec


class Verdict(msgspec.Struct):
    """One line of the table: what was checked, what the spec requires, what was measured."""

    what: str
    required: str
    measured: str
    ok: bool
    why: str = ""  # when it fails: what went wrong, by how much


def table(verdicts: list[Verdict]) -> str:
    """criterion | required | measured | verdict, aligned; a failing row's reason beneath it;
    then how many hold."""
    rows = [("criterion", "required", "measured", "verdict")] + [
        (v.what, v.required, v.measured, "ok" if v.ok else "FAIL") for v in verdicts
    ]
    widths = [max(len(r[k]) for r in rows) for k in range(3)]
    lines = []
    for i, r in enumerate(rows):
        lines.append("  ".join(cell.ljust(w) for cell, w in zip(r[:3], widths, strict=True)) + "  " + r[3])
        if i and not verdicts[i - 1].ok and verdicts[i - 1].why:
            lines.append(f"    why: {verdicts[i - 1].why}")
    held = sum(v.ok for v in verdicts)
    lines.append(
        f"{held} of {len(verdicts)} hold" + ("" if held == len(verdicts) else f"; {len(verdicts) - held} fail")
    )
    return "\n".join(lines)


def as_json(verdicts: list[Verdict]) -> str:
    return msgspec.json.encode({"ok": all(v.ok for v in verdicts), "verdicts": verdicts}).decode()
