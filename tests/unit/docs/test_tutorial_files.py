"""The tutorial "Write your own node" shows the example project's files as they are: each code block
whose first line names a file (``# patrol.py``) holds that file of examples/patrol, whole."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
TUTORIAL = ROOT / "docs" / "tutorials" / "your-own-node.md"
EXAMPLE = ROOT / "examples" / "patrol"


def shown_files(text: str) -> dict[str, str]:
    """File name -> the block's text after its naming line, for blocks that name a file."""
    found = {}
    for body in re.findall(r"```(?:python|ini)\n(.*?)```", text, re.DOTALL):
        first, _, rest = body.partition("\n")
        if re.fullmatch(r"# [\w/]+\.(py|ini)", first):
            found[first[2:]] = rest
    return found


def test_the_tutorial_shows_the_example_files_whole():
    shown = shown_files(TUTORIAL.read_text())
    assert set(shown) == {"patrol.py", "messages.py", "tests/test_patrol.py", "tests/test_system.py", "pytest.ini"}
    for name, text in shown.items():
        assert text == (EXAMPLE / name).read_text(), f"{name}: the tutorial's copy differs from examples/patrol/{name}"


def test_the_launch_file_shown_is_the_examples():
    assert "```toml\n" + (EXAMPLE / "launch.toml").read_text() + "```" in TUTORIAL.read_text()
