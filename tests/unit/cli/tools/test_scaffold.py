"""cli.tools.scaffold and `turtlectl new node`: a node to start from that passes its own test and
its launch file's check; names and files that cannot be used refused, nothing overwritten."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from turtlectl.cli.tools.scaffold import camel, node_files
from turtlectl.runtime.client.errors import BadInput

TURTLECTL = [str(Path(sys.executable).parent / "turtlectl")]


def test_names_become_classes_and_bad_names_are_refused(tmp_path):
    assert camel("wall_follower") == "WallFollower"
    for bad in ("Patrol", "wall-follower", "1st", "class", ""):
        with pytest.raises(BadInput, match="snake_case"):
            node_files(bad, tmp_path)


def test_nothing_is_overwritten_and_a_pytest_ini_is_kept(tmp_path):
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    files = node_files("patrol", tmp_path)
    assert set(files) == {tmp_path / "patrol.py", tmp_path / "tests" / "test_patrol.py"}
    (tmp_path / "patrol.py").write_text("mine")
    with pytest.raises(BadInput, match="patrol.py exists already"):
        node_files("patrol", tmp_path)


def test_the_new_node_passes_its_test_and_its_launch_entry_checks(tmp_path):
    made = subprocess.run([*TURTLECTL, "new", "node", "wall_follower"], cwd=tmp_path, capture_output=True, text=True)
    assert made.returncode == 0, made.stderr
    entry = made.stdout.split("add to your launch.toml:\n\n", 1)[1].split("\nthen:", 1)[0]
    (tmp_path / "launch.toml").write_text('[[node]]\nname = "sim"\nrun = "sim"\n\n' + entry)
    checked = subprocess.run([*TURTLECTL, "launch", "--check"], cwd=tmp_path, capture_output=True, text=True)
    assert checked.returncode == 0 and "wall_follower (run ./wall_follower.py:WallFollower" in checked.stdout, checked
    tested = subprocess.run(
        [str(Path(sys.executable).parent / "pytest"), "-q", "-p", "no:cacheprovider"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert tested.returncode == 0 and "1 passed" in tested.stdout, tested.stdout
    again = subprocess.run([*TURTLECTL, "new", "node", "wall_follower"], cwd=tmp_path, capture_output=True, text=True)
    assert again.returncode == 2 and again.stderr.startswith("turtlectl: error: new node wall_follower: ")
