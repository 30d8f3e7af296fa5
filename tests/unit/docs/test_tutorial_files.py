"""The tutorial "Write your own node" shows the example projects' files as they are: each code block
whose first line names a file (``# patrol.py``: examples/patrol; ``# capstone/navigator.py``:
examples/capstone) holds that file, whole."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
TUTORIAL = ROOT / "docs" / "tutorials" / "your-own-node.md"
EXAMPLE = ROOT / "examples" / "patrol"
CAPSTONE = "capstone/"


def shown_files(text: str) -> dict[str, str]:
    """File name -> the block's text after its naming line, for blocks that name a file."""
    found = {}
    for body in re.findall(r"```(?:python|ini|toml)\n(.*?)```", text, re.DOTALL):
        first, _, rest = body.partition("\n")
        if re.fullmatch(r"# [\w/]+\.(py|ini|toml)", first):
            found[first[2:]] = rest
    return found


def example_file(name: str) -> Path:
    """Where a file the tutorial names lies: examples/capstone/ for capstone/..., else examples/patrol/."""
    if name.startswith(CAPSTONE):
        return ROOT / "examples" / "capstone" / name.removeprefix(CAPSTONE)
    return EXAMPLE / name


def test_the_tutorial_shows_the_example_files_whole():
    shown = shown_files(TUTORIAL.read_text())
    assert set(shown) == {
        "patrol.py",
        "messages.py",
        "tests/test_patrol.py",
        "tests/test_system.py",
        "pytest.ini",
        "capstone/capstone_msgs.py",
        "capstone/navigator.py",
        "capstone/launch.toml",
        "capstone/tests/test_navigator.py",
        "capstone/tests/test_system.py",
        "capstone/pytest.ini",
    }
    for name, text in shown.items():
        path = example_file(name)
        assert text == path.read_text(), f"{name}: the tutorial's copy differs from {path.relative_to(ROOT)}"


def test_the_launch_file_shown_is_the_examples():
    assert "```toml\n" + (EXAMPLE / "launch.toml").read_text() + "```" in TUTORIAL.read_text()


def test_the_capstone_spec_shown_is_the_examples_status_topic():
    spec = (ROOT / "examples" / "capstone" / "capstone.toml").read_text()
    shown = re.search(r'```toml\n(\[\[topic\]\]\nkey = "robot/status"\n.*?)```', TUTORIAL.read_text(), re.DOTALL)
    assert shown is not None and shown.group(1) in spec
