"""One rule for infinities and NaN in JSON, said where a reader looks: the interfaces in short
(docs/how-to/raw-clients.md, once the README's Interfaces section) and docs/interfaces.md say
"Infinity" (as recordings, the Foxglove server and ``echo --json`` write it), never ``null``; the
record-and-replay guide (once the README's section) says each recorded channel's encoding."""

from pathlib import Path

from turtlectl.messages.reference import FIELDS

ROOT = Path(__file__).resolve().parents[3]
DOC = (ROOT / "docs" / "interfaces.md").read_text()
PAGES = {"Interfaces": "how-to/raw-clients.md", "Recording and replay": "how-to/record-and-replay.md"}


def _section(title: str) -> str:
    return (ROOT / "docs" / PAGES[title]).read_text()


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
