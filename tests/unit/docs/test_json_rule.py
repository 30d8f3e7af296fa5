"""One rule for infinities and NaN in JSON, said where a reader looks: the README's Interfaces
section and docs/interfaces.md say "Infinity" (as recordings, the Foxglove server and
``echo --json`` write it), never ``null``; the README says each recorded channel's encoding."""

from pathlib import Path

from messages.reference import FIELDS

ROOT = Path(__file__).resolve().parents[3]
README = (ROOT / "README.md").read_text()
DOC = (ROOT / "docs" / "interfaces.md").read_text()


def _section(title: str) -> str:
    return README.split(f"\n## {title}\n", 1)[1].split("\n## ", 1)[0]


def test_the_interfaces_section_and_the_reference_spell_infinity_as_recordings_do():
    interfaces = _section("Interfaces")
    assert "`null` in JSON" not in interfaces and '`"Infinity"` in JSON' in interfaces
    assert '`"Infinity"`, `"-Infinity"` or `"NaN"`' in interfaces  # the rule, once, for every JSON
    assert "null in `echo --json`" not in DOC and "``null`` in `echo --json`" not in DOC
    assert '"Infinity"' in DOC.split("## ", 2)[1]  # in the conventions at the top, before the types
    assert "null" not in FIELDS["LaserScan"]["ranges"][-1]


def test_the_recording_section_says_each_channels_encoding():
    recording = _section("Recording and replay")
    assert "each message JSON" not in recording
    assert "`json` for turtlectl's messages" in recording and "`protobuf` for the scene" in recording
    assert "scene's included" in recording
