"""cli.system.launchfile with a ``cmd`` node (any program, as ROS's
ExecuteProcess): exactly one of run and cmd, the program exists and is executable (relative
to the launch file), no params; ``launch --check`` says so in one line."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from turtlectl.cli.system.launchfile import LaunchFileError, load_launch
from turtlectl.cli.system.overrides import node_config, parse_assignment, select_nodes, with_overrides
from turtlectl.cli.tools.format import plan_text

SIM = '[[node]]\nname = "sim"\nrun = "sim"\n'


def _file(tmp_path: Path, node: str) -> Path:
    path = tmp_path / "launch.toml"
    path.write_text(SIM + "[[node]]\n" + node, encoding="utf-8")
    return path


def _driver(tmp_path: Path, mode: int = 0o755) -> Path:
    driver = tmp_path / "driver"
    driver.write_text("#!/bin/sh\nexec sleep 1000\n", encoding="utf-8")
    driver.chmod(mode)
    return driver


def test_a_cmd_is_resolved_relative_to_the_launch_file(tmp_path: Path) -> None:
    driver = _driver(tmp_path)
    plan = load_launch(_file(tmp_path, 'name = "driver"\ncmd = ["./driver", "--port", "/dev/ttyUSB0"]\n'))
    assert plan.commands == {"driver": [str(driver), "--port", "/dev/ttyUSB0"]}
    assert "driver" not in plan.kinds and plan.params["driver"] == {}
    assert "driver (cmd ./driver --port /dev/ttyUSB0; optional)" in plan_text(plan)
    assert select_nodes(plan, ["driver"], []).commands == plan.commands
    assert select_nodes(plan, [], ["driver"]).commands == {}


def test_a_bare_program_name_comes_from_path(tmp_path: Path) -> None:
    plan = load_launch(_file(tmp_path, 'name = "s"\ncmd = ["sleep", "1"]\n'))
    assert os.path.basename(plan.commands["s"][0]) == "sleep"


@pytest.mark.parametrize(
    ("node", "message"),
    [
        ('name = "d"\nrun = "navigator"\ncmd = ["./driver"]\n', "node[1] (d): both run and cmd: give run"),
        ('name = "d"\n', "node[1] (d): neither run nor cmd: give run"),
        ('name = "d"\ncmd = []\n', "node[1] (d): neither run nor cmd: give run"),
        ('name = "d"\ncmd = [""]\n', "node[1] (d).cmd: name a program"),
        ('name = "d"\ncmd = "./driver"\n', "node[1] (d).cmd must be a list"),
        ('name = "d"\ncmd = ["./driver", 3]\n', "node[1] (d).cmd[1] must be text"),
        ('name = "d"\ncmd = ["./nothing"]\n', "node[1] (d).cmd: ./nothing does not exist"),
        (
            'name = "d"\ncmd = ["no-such-program-here"]\n',
            "node[1] (d).cmd: no-such-program-here: no such program on PATH",
        ),
        ('name = "d"\ncmd = ["./driver"]\nparams = { port = 1 }\n', "node[1] (d).params: a cmd node has no parameters"),
    ],
)
def test_bad_cmd_nodes_are_one_line(tmp_path: Path, node: str, message: str) -> None:
    _driver(tmp_path)
    path = _file(tmp_path, node)
    with pytest.raises(LaunchFileError) as err:
        load_launch(path)
    assert str(err.value).startswith(f"{path}: {message}"), str(err.value)
    assert "\n" not in str(err.value)


def test_a_program_that_is_not_executable_is_refused(tmp_path: Path) -> None:
    _driver(tmp_path, mode=0o644)
    path = _file(tmp_path, 'name = "driver"\ncmd = ["./driver"]\n')
    with pytest.raises(LaunchFileError) as err:
        load_launch(path)
    assert str(err.value) == f"{path}: node[1] (driver).cmd: ./driver is not executable"


def test_overrides_keep_cmd_nodes_and_give_them_no_params(tmp_path: Path) -> None:
    _driver(tmp_path)
    plan = load_launch(_file(tmp_path, 'name = "driver"\ncmd = ["./driver"]\nrespawn = true\n'))
    again = with_overrides(plan, [parse_assignment("sim.x=3", "--set", "")], "--set")
    assert again.commands == plan.commands and again.launch.node[1].respawn
    with pytest.raises(LaunchFileError, match=r"--set driver: a cmd node has no parameters"):
        with_overrides(plan, [parse_assignment("driver.port=3", "--set", "")], "--set")
    with pytest.raises(LaunchFileError, match="driver runs a program"):
        node_config(plan, "driver", "tcp/127.0.0.1:1")
