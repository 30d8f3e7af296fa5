"""One table of exit codes for every turtlectl process: a command and a
node process give each number the same meaning, docs/reference/exit-codes.md lists each, and
the supervisor respawns only the exits that a new start could change."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from turtlectl.runtime.exitcodes import ExitCode, node_exit, respawn_can_help

ROOT = Path(__file__).resolve().parents[3]


def test_commands_and_node_processes_use_the_one_table():
    from turtlectl.runtime import lifecycle
    from turtlectl.runtime.client import errors

    assert errors.ExitCode is ExitCode
    # no second table of numbers beside it
    assert not [name for name in vars(lifecycle) if name.startswith("EXIT_")]
    assert not [name for name in vars(errors) if re.fullmatch(r"[A-Z_]+", name) and name != "EXIT_CODES"]


def test_the_reference_documents_every_code_of_the_table_and_no_other():
    section = (ROOT / "docs" / "reference" / "exit-codes.md").read_text()
    documented = {int(m) for m in re.findall(r"^\| (\d+) \|", section, re.MULTILINE)}
    assert documented == {int(code) for code in ExitCode}


@pytest.mark.parametrize(
    "code, helps",
    [(0, True), (1, True), (3, True), (-9, True), (-11, True), (2, False), (4, False), (5, True), (130, True)],
)
def test_only_a_configuration_error_or_a_conflict_is_not_worth_a_respawn(code, helps):
    assert respawn_can_help(code) is helps


def test_a_node_s_exit_is_described_by_what_it_means_for_a_node():
    assert node_exit(2) == "exited with code 2 (bad input: its configuration or its declarations cannot be used)"
    assert node_exit(4) == "exited with code 4 (could not start: another process already holds what it claims)"
    assert node_exit(1) == "exited with code 1"
    assert node_exit(-9) == "was killed by SIGKILL"
