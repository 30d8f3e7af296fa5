"""Launch-file validation: every mistake names the file and the exact key path."""

from pathlib import Path

import pytest

from cli.launchfile import LaunchFileError, load_launch, parse_launch
from cli.main import PACKAGED_LAUNCH

ROOT = Path(__file__).resolve().parent.parent

MINIMAL = '[[node]]\nname = "sim"\nrun = "sim"\n'


def test_default_launch_file_is_valid_and_packaged():
    plan = load_launch(ROOT / "launch.toml")
    assert [e.name for e in plan.launch.node] == ["sim", "navigator", "status_monitor", "obstacle_detector"]
    assert len(plan.launch.world.obstacles) == 3
    assert PACKAGED_LAUNCH.read_text() == (ROOT / "launch.toml").read_text()


def test_defaults_are_filled_in():
    plan = parse_launch(MINIMAL)
    assert plan.params["sim"]["cmd_timeout"] == 1.0
    assert plan.launch.node[0].required is False


@pytest.mark.parametrize(
    "text, message",
    [
        (MINIMAL + "colour = 1\n", "f.toml: node[0].colour: unknown key"),
        (MINIMAL + "[node.params]\nx = 'left'\n", "f.toml: node[0].params.x: Expected `float`, got `str`"),
        (MINIMAL + "[node.params]\ncmd_timeout = -1\n", "f.toml: node[0].params.cmd_timeout: Expected `float` > 0.0"),
        (MINIMAL + "[node.params]\nspeed = 3\n", "f.toml: node[0].params.speed: unknown key"),
        (MINIMAL + "respawn = 'yes'\n", "f.toml: node[0].respawn: Expected `bool`, got `str`"),
        ("[world]\nsize = 0\n" + MINIMAL, "f.toml: world.size: Expected `float` > 0.0"),
        ("[world]\nobstacles = [{x = 1, y = 1}]\n" + MINIMAL, "f.toml: world.obstacles[0].radius: missing required key"),
        ("[limits]\nmax_linear_speed = 'fast'\n" + MINIMAL, "f.toml: limits.max_linear_speed: Expected `float`"),
        ('[[node]]\nname = "a"\n', "f.toml: node[0].run: missing required key"),
        ('[[node]]\nname = "a"\nrun = "turtle"\n', "f.toml: node[0].run: unknown node kind 'turtle'"),
        (MINIMAL + MINIMAL, "f.toml: node[1].name: duplicate node name 'sim'"),
        ('[[node]]\nname = "a/b"\nrun = "sim"\n', "f.toml: node[0].name: 'a/b' is not a valid name"),
        ("", "f.toml: node: missing required key"),
        ("node = []\n", "f.toml: node: the launch file lists no node"),
        ("[[node]\n", "f.toml: not valid TOML"),
        (
            '[[node]]\nname = "n"\nrun = "navigator"\n[node.params.gains]\nk_linear = "x"\n',
            "f.toml: node[0].params.gains.k_linear: Expected `float`, got `str`",
        ),
    ],
)
def test_errors_name_the_key_path(text, message):
    with pytest.raises(LaunchFileError) as err:
        parse_launch(text, source="f.toml")
    assert str(err.value).startswith(message), str(err.value)


def test_missing_file(tmp_path):
    with pytest.raises(LaunchFileError, match="cannot read"):
        load_launch(tmp_path / "nope.toml")
