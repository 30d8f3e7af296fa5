"""The verdicts of ``turtlectl verify`` as one table for people, or one JSON object (pure)."""

from __future__ import annotations

from pathlib import Path

import msgspec

from turtlectl.runtime.client.errors import BadInput


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


def junit(suite: str, verdicts: list[Verdict]) -> str:
    """The verdicts as a JUnit XML report: one testcase per line of the table, a failing one
    with its reason (what CI systems show as test results)."""
    from xml.etree import ElementTree as ET

    failures = sum(not v.ok for v in verdicts)
    root = ET.Element("testsuites", tests=str(len(verdicts)), failures=str(failures))
    cases = ET.SubElement(root, "testsuite", name=suite, tests=str(len(verdicts)), failures=str(failures))
    for v in verdicts:
        case = ET.SubElement(cases, "testcase", classname="turtlectl.verify", name=v.what)
        ET.SubElement(case, "system-out").text = f"required: {v.required}\nmeasured: {v.measured}"
        if not v.ok:
            ET.SubElement(
                case, "failure", message=v.why or "does not hold"
            ).text = f"required: {v.required}; measured: {v.measured}"
    return ET.tostring(root, encoding="unicode", xml_declaration=True)


def write(path: Path, text: str, what: str) -> None:
    """``text`` written to ``path``; BadInput (exit 2) saying ``what`` and why if it cannot be."""
    try:
        path.write_text(text)
    except OSError as exc:
        raise BadInput(f"{what}: {exc.strerror or exc}") from None


def write_junit(path: Path, suite: str, verdicts: list[Verdict]) -> None:
    """``junit`` written to ``path`` (BadInput, exit 2, if it cannot be)."""
    write(path, junit(suite, verdicts) + "\n", f"--junit {path}: cannot write")
