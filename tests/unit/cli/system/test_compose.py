"""Launch composition (cli.system.compose and its use by the launch file): arguments
with defaults and descriptions (``[arg.NAME]``, ``$(arg NAME)``, ``--arg NAME=VALUE``), includes of
other launch files with arguments and a namespace (``[[include]]``), and a node's ``remap``.
Errors name the chain of files and the key path; a cycle of includes is refused."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from turtlectl.cli.system.launchfile import LaunchFileError, load_launch, parse_launch
from turtlectl.cli.system.overrides import launch_plan, node_config
from turtlectl.cli.tools.format import plan_text

SIM = '[[node]]\nname = "sim"\nrun = "sim"\n'

TURTLE = """
[arg.timeout]
default = 30.0
description = "s before a goal fails"

[arg.robot]
description = "no default: the including file gives it"

[[node]]
name = "navigator"
run = "navigator"
remap = { "turtle1/cmd_vel" = "safety/cmd_vel" }
[node.params]
goal_timeout = "$(arg timeout)"

[[node]]
name = "$(arg robot)_relay"
run = "./relay.py:Relay"
"""

RELAY = """
import msgspec


class Relay:
    Params = msgspec.defstruct("RelayParams", [])
"""


def files(folder: Path, **texts: str) -> Path:
    """Write each ``name=text`` (``robots__turtle`` is robots/turtle.toml); the first one's path."""
    paths = []
    for name, text in texts.items():
        path = folder / (name.replace("__", "/") + (".py" if name.endswith("relay") else ".toml"))
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text))
        paths.append(path)
    return paths[0]


def test_an_include_brings_its_nodes_with_the_arguments_it_is_given_and_a_namespace(tmp_path):
    top = files(
        tmp_path,
        launch="""
        [arg.speed]
        default = 2.0
        description = "how fast"

        [[node]]
        name = "sim"
        run = "sim"

        [[include]]
        file = "robots/turtle.toml"
        args = { robot = "first" }

        [[include]]
        file = "robots/turtle.toml"
        namespace = "/turtle2"
        args = { timeout = 45, robot = "second" }
        """,
        robots__turtle=TURTLE,
        robots__relay=RELAY,
    )
    plan = load_launch(top)
    names = [e.name for e in plan.launch.node]
    assert names == ["sim", "navigator", "first_relay", "turtle2/navigator", "turtle2/second_relay"]
    assert plan.params["navigator"]["goal_timeout"] == 30.0  # the default
    assert plan.params["turtle2/navigator"]["goal_timeout"] == 45.0  # given 45: taken as its default's float
    # a ./file.py:Class of an included file is relative to it, written from the top file's folder
    assert plan.launch.node[2].run == "./robots/relay.py:Relay"
    assert plan.remaps == {
        "navigator": {"turtle1/cmd_vel": "safety/cmd_vel"},
        "turtle2/navigator": {"turtle1/cmd_vel": "safety/cmd_vel"},
    }
    given = {(a.file, a.name): (a.value, a.given) for a in plan.args}
    assert given[(str(top), "speed")] == (2.0, "default")
    assert given[(f"{top} -> include[1] (turtle2) robots/turtle.toml", "robot")] == ("second", f"include[1] of {top}")


def test_a_remap_reaches_the_nodes_config_its_keys_interface_and_claims(tmp_path):
    top = files(
        tmp_path,
        launch=SIM + '[[include]]\nfile = "t.toml"\nnamespace = "turtle2"\nargs = { robot = "r" }\n',
        t=TURTLE,
        relay=RELAY,
    )
    config = node_config(load_launch(top), "turtle2/navigator", "tcp/127.0.0.1:7447")
    assert config.remaps == {"turtle1/cmd_vel": "safety/cmd_vel"}
    assert config.interface is not None and "turtle2/safety/cmd_vel" in config.interface.publishes
    assert "turtle2/cmd_vel" not in config.interface.publishes
    assert [c.key for c in config.claims] == ["turtle2/navigate_to"]
    assert "remap turtle2/cmd_vel -> turtle2/safety/cmd_vel" in plan_text(load_launch(top))


def test_command_line_arguments_are_typed_from_their_defaults(tmp_path):
    top = files(
        tmp_path,
        launch="""
        [arg.timeout]
        default = 30.0
        [arg.name]
        default = "1"
        [arg.respawn]
        default = false
        [arg.both]
        default = "$(arg name)_$(arg timeout)"    # a default may use the arguments above it

        [[node]]
        name = "nav_$(arg name)"
        run = "navigator"
        respawn = "$(arg respawn)"
        [node.params]
        goal_timeout = "$(arg timeout)"
        """,
    )
    plan = launch_plan(top, [], [], [], arguments=["timeout=60", "name = 2", "respawn:=true"])  # ROS's := too
    assert plan.launch.node[0].name == "nav_2"  # a text argument takes the text as written
    assert plan.params["nav_2"]["goal_timeout"] == 60.0 and plan.launch.node[0].respawn is True
    assert {a.name: a.value for a in plan.args}["both"] == "2_60.0"
    text = plan_text(plan)
    assert "arguments:" in text and f"{top}: timeout = 60.0 (--arg; default 30.0)" in text


@pytest.mark.parametrize(
    "arguments, message",
    [
        (["speeed=2"], "--arg speeed=2: {top} declares no argument speeed; did you mean speed? (its arguments: speed)"),
        (["speed=fast"], "--arg speed=fast: {top}'s argument speed is a number (its default: 2.0), not a text"),
        (["speed"], "--arg 'speed': write it as NAME=VALUE"),
    ],
)
def test_an_argument_the_file_does_not_declare_or_cannot_take_is_refused(tmp_path, arguments, message):
    top = files(tmp_path, launch='[arg.speed]\ndefault = 2.0\n[[node]]\nname = "sim"\nrun = "sim"\n')
    with pytest.raises(LaunchFileError) as err:
        load_launch(top, arguments)
    assert str(err.value).startswith(message.format(top=top)), str(err.value)


def test_an_argument_without_a_default_must_be_given(tmp_path):
    top = files(tmp_path, launch="[arg.robot]\n" + SIM)
    with pytest.raises(LaunchFileError, match=r"launch.toml: arg.robot: no value: give one, --arg robot=VALUE"):
        load_launch(top)
    assert load_launch(top, ["robot=r2"]).args[0].value == "r2"


@pytest.mark.parametrize(
    "texts, message",
    [
        # the include of a missing file names the including file and the key
        (
            {"launch": SIM + '[[include]]\nfile = "robots/nope.toml"\n'},
            "launch.toml: include[0].file: robots/nope.toml: no such file",
        ),
        # an argument the included file does not declare, at the include's key path
        (
            {"launch": SIM + '[[include]]\nfile = "t.toml"\nargs = { robot = "r", timout = 3 }\n', "t": TURTLE},
            "launch.toml: include[0].args.timout: t.toml declares no argument timout; did you mean timeout? "
            "(its arguments: timeout, robot)",
        ),
        (
            {"launch": SIM + '[[include]]\nfile = "t.toml"\n', "t": TURTLE},
            "launch.toml: include[0].args: t.toml's argument robot has no default: give it, args = { robot = ... }",
        ),
        (
            {"launch": SIM + '[[include]]\nfile = "t.toml"\nargs = { robot = "r", timeout = "long" }\n', "t": TURTLE},
            "launch.toml: include[0].args.timeout: t.toml's argument timeout is a number (its default: 30.0)",
        ),
        # a cycle, through another file or straight back
        (
            {"launch": SIM + '[[include]]\nfile = "b.toml"\n', "b": '[[include]]\nfile = "launch.toml"\n'},
            "launch.toml -> include[0] b.toml -> include[0] launch.toml: include cycle",
        ),
        (
            {"launch": SIM + '[[include]]\nfile = "./launch.toml"\n'},
            "launch.toml -> include[0] ./launch.toml: include cycle",
        ),
        # errors inside an included file name the chain of files, then the key path
        (
            {"launch": SIM + '[[include]]\nfile = "t.toml"\nargs = { robot = "r", timeout = 0.0 }\n', "t": TURTLE},
            "launch.toml -> include[0] t.toml: node[0] (navigator).params.goal_timeout must be >= 0.1",
        ),
        (
            {
                "launch": SIM + '[[include]]\nfile = "t.toml"\n',
                "t": '[[node]]\nname = "n"\nrun = "navigator"\nrespawn = "$(arg again)"\n',
            },
            "launch.toml -> include[0] t.toml: node[0] (n).respawn: $(arg again): the file declares no argument again "
            "(it declares none: add [arg.NAME])",
        ),
        (
            {"launch": "[arg.a]\ndefault = 1\n" + SIM.replace('"sim"\n', '"sim"\nrequired = "$(env A)"\n', 1)},
            "launch.toml: node[0] (sim).required: $(env A): not a substitution; write $(arg NAME)",
        ),
        (
            {
                "launch": SIM + '[[include]]\nfile = "t.toml"\n',
                "t": '[[node]]\nname = "n"\nrun = "navigator"\nrespawn = "yes"\n',
            },
            "launch.toml -> include[0] t.toml: node[0] (n).respawn must be true or false",
        ),
        # the system has one world, written in any one of its files
        (
            {"launch": "[world]\nsize = 20\n" + SIM + '[[include]]\nfile = "w.toml"\n', "w": "[world]\nsize = 10\n"},
            "launch.toml -> include[0] w.toml: world: {dir}/launch.toml writes [world] too: a launch has one [world]",
        ),
        # namespaces do not nest, and a file included twice in one namespace is two of each node
        (
            {
                "launch": SIM + '[[include]]\nfile = "g.toml"\nnamespace = "turtle2"\n',
                "g": '[[group]]\nnamespace = "turtle3"\n[[group.node]]\nname = "n"\nrun = "navigator"\n',
            },
            "launch.toml -> include[0] (turtle2) g.toml: group[0].namespace: the file is included in namespace 'turtle2': namespaces do not nest",
        ),
        (
            {
                "launch": SIM + '[[include]]\nfile = "n.toml"\n[[include]]\nfile = "n.toml"\n',
                "n": '[[node]]\nname = "n"\nrun = "navigator"\n',
            },
            "launch.toml -> include[1] n.toml: node[0] (n).name: duplicate node name 'n' (its file is included twice: "
            "give each [[include]] a namespace)",
        ),
        ({"launch": SIM + '[[includ]]\nfile = "n.toml"\n'}, "launch.toml: includ: unknown key; did you mean include?"),
        ({"launch": SIM + "[arg.x]\ndefalt = 1\n"}, "launch.toml: arg.x.defalt: unknown key; did you mean default?"),
        ({"launch": SIM + "[arg]\nx = 1\n"}, "launch.toml: arg.x: write it as a table, [arg.NAME] with default = ..."),
        # remaps: keys, never the runtime's own, and (for a kind that declares its keys) one the node uses
        (
            {"launch": SIM + '[[node]]\nname = "n"\nrun = "navigator"\nremap = { "turtle1/cmd_vell" = "x" }\n'},
            'launch.toml: node[1] (n).remap."turtle1/cmd_vell": the node uses no key turtle1/cmd_vell (its keys: '
            "turtle1/cmd_vel, navigate_to/feedback,",
        ),
        (
            {
                "launch": SIM
                + '[[node]]\nname = "n"\nrun = "navigator"\nnamespace = "turtle2"\nremap = { "turtle2/pose" = "x" }\n'
            },
            'launch.toml: node[1] (turtle2/n).remap."turtle2/pose": the node uses no key turtle2/turtle2/pose',
        ),
        (
            {
                "launch": SIM
                + '[[node]]\nname = "n"\nrun = "navigator"\nremap = { "turtle1/pose" = "turtlectl/pose" }\n'
            },
            'launch.toml: node[1] (n).remap."turtle1/pose": turtlectl/pose is one of the runtime\'s own keys',
        ),
        (
            {"launch": SIM + '[[node]]\nname = "n"\nrun = "navigator"\nremap = { "turtle1/pose" = "*/pose" }\n'},
            "launch.toml: node[1] (n).remap.\"turtle1/pose\": '*/pose' is not a key",
        ),
        (
            {"launch": SIM + '[[node]]\nname = "n"\ncmd = ["true"]\nremap = { "a" = "b" }\n'},
            "launch.toml: node[1] (n).remap: a cmd node has no keys of a turtlectl node to remap",
        ),
    ],
)
def test_errors_name_the_chain_of_files_and_the_key_path(tmp_path, texts, message):
    top = files(tmp_path, **texts)
    with pytest.raises(LaunchFileError) as err:
        load_launch(top)
    assert str(err.value).startswith(f"{tmp_path}/{message}".replace("{dir}", str(tmp_path))), str(err.value)


def test_an_included_file_may_write_the_world_when_no_other_does(tmp_path):
    top = files(
        tmp_path,
        launch=SIM + '[[include]]\nfile = "w.toml"\n',
        w="[world]\nsize = 20\n[limits]\nmax_linear_speed = 1.0\n",
    )
    plan = load_launch(top)
    assert plan.launch.world.size == 20.0 and plan.launch.limits.max_linear_speed == 1.0


def test_a_world_mistake_in_an_included_file_names_it(tmp_path):
    top = files(
        tmp_path,
        launch=SIM + '[[include]]\nfile = "w.toml"\n',
        w="[world]\nobstacles = [{x = 50, y = 5, radius = 1}]\n",
    )
    with pytest.raises(
        LaunchFileError, match=r"launch.toml -> include\[0\] w.toml: world.obstacles\[0\]: centre \(50, 5\)"
    ):
        load_launch(top)


def test_two_navigators_in_one_namespace_remapped_apart_claim_different_keys():
    text = SIM + '[[node]]\nname = "a"\nrun = "navigator"\n[[node]]\nname = "b"\nrun = "navigator"\n'
    with pytest.raises(LaunchFileError, match="a second 'navigator' node"):
        parse_launch(text, source="f.toml")
    plan = parse_launch(text + 'remap = { navigate_to = "b/navigate_to", "navigate_to/cancel" = "b/cancel" }\n')
    assert [e.name for e in plan.launch.node] == ["sim", "a", "b"]


def test_without_includes_or_arguments_a_file_is_as_before():
    plan = parse_launch(SIM, source="f.toml")
    assert plan.args == [] and plan.remaps == {} and "arguments:" not in plan_text(plan)


EXAMPLE = Path(__file__).resolve().parents[4] / "examples" / "compose"


def test_the_example_is_valid_and_the_how_to_shows_its_files():
    plan = load_launch(EXAMPLE / "launch.toml", ["speed_limit=0.8"])
    assert (
        plan.params["turtle2/speed_limit"]["max_speed"] == 0.8
        and plan.params["turtle2/navigator"]["goal_timeout"] == 60.0
    )
    page = (EXAMPLE.parents[1] / "docs" / "how-to" / "compose.md").read_text()
    for block in page.split("```toml\n")[1:]:
        first, *lines = block.split("```")[0].splitlines()
        if first.startswith("# examples/compose/"):
            text = (EXAMPLE / first.split()[1].rpartition("/")[2].rstrip(":")).read_text()
            for line in lines:
                code = line.split("#")[0].strip()
                assert code in text, (first, line)  # every line shown (comments aside) is the example's


# -- launch composition as a new user writes it -----------------------------------------------
REVIEW_TOP = """
[arg.speed]
default = 1.0
[arg.t2_timeout]
default = 40.0

[[node]]
name = "sim"
run = "sim"

[[include]]
file = "robots/robot.toml"
args = { max_speed = "$(arg speed)" }

[[include]]
file = "robots/robot.toml"
namespace = "turtle2"
args = { max_speed = "$(arg speed)", timeout = "$(arg t2_timeout)", label = "r_$(arg speed)" }
"""

REVIEW_ROBOT = """
[arg.max_speed]
[arg.timeout]
default = 30.0
[arg.label]
default = "r"

[[node]]
name = "navigator"
run = "navigator"
[node.params]
goal_timeout = "$(arg timeout)"

[[node]]
name = "limiter"
run = "status_monitor"
[node.params]
rate = "$(arg max_speed)"
"""


def test_an_argument_of_an_included_file_given_on_the_command_line_says_to_pass_it_through_args(tmp_path):
    top = files(tmp_path, top=REVIEW_TOP, robots__robot=REVIEW_ROBOT)
    with pytest.raises(LaunchFileError) as err:
        load_launch(top, ["max_speed=1"])
    assert str(err.value) == (
        f"--arg max_speed=1: max_speed is an argument of robots/robot.toml (include[0]), not of {top}: a file "
        'sees only its own arguments; pass it through that include\'s args, as args = { max_speed = "$(arg ...)" }'
    )


def test_the_chain_names_the_include_and_its_namespace_in_check_and_in_errors(tmp_path):
    top = files(tmp_path, top=REVIEW_TOP, robots__robot=REVIEW_ROBOT)
    text = plan_text(load_launch(top))
    assert f"  {top} -> include[0] robots/robot.toml: max_speed = 1.0 (include[0] of {top}; no default)" in text
    assert f"  {top} -> include[1] (turtle2) robots/robot.toml: timeout = 40.0 (include[1] of {top}" in text
    with pytest.raises(LaunchFileError) as err:
        load_launch(top, ["t2_timeout=0"])
    assert str(err.value).startswith(
        f"{top} -> include[1] (turtle2) robots/robot.toml: node[0] (turtle2/navigator).params.goal_timeout "
        "must be >= 0.1 (got 0.0)"
    ), str(err.value)


def test_a_value_error_says_which_argument_the_value_came_from(tmp_path):
    top = files(tmp_path, top=REVIEW_TOP, robots__robot=REVIEW_ROBOT)
    with pytest.raises(LaunchFileError) as err:
        load_launch(top, ["speed=0"])
    assert str(err.value).startswith(
        f"{top} -> include[0] robots/robot.toml: node[1] (limiter).params.rate must be >= 0.1 (got 0.0)"
    ) and str(err.value).endswith(" (from --arg speed through include[0].args.max_speed)"), str(err.value)
    with pytest.raises(LaunchFileError) as err:
        parse_launch("[arg.t]\ndefault = 0.0\n" + SIM + '[node.params]\ncmd_timeout = "$(arg t)"\n', "f.toml")
    assert str(err.value).endswith("(from arg.t's default)"), str(err.value)


@pytest.mark.parametrize(
    "texts, message",
    [
        ({"launch": SIM + 'required = "$(arg x"\n'}, 'launch.toml: node[0] (sim).required: "$(arg x": unclosed $(...)'),
        (
            {"launch": SIM + '[[include]]\nfile = "sub"\n', "sub__x": ""},
            "launch.toml: include[0].file: sub is a folder",
        ),
    ],
)
def test_review_nits_unclosed_substitution_and_an_included_folder(tmp_path, texts, message):
    top = files(tmp_path, **texts)
    with pytest.raises(LaunchFileError) as err:
        load_launch(top)
    assert str(err.value).startswith(f"{tmp_path}/{message}"), str(err.value)


def test_type_errors_show_values_as_toml_writes_them(tmp_path):
    top = files(tmp_path, launch='[arg.fast]\ndefault = true\n[arg.name]\ndefault = "n"\n' + SIM)
    with pytest.raises(LaunchFileError) as err:
        load_launch(top, ["fast=2"])
    assert str(err.value).endswith("is a boolean (its default: true), not an integer (2)"), str(err.value)
    sub = files(
        tmp_path,
        launch=SIM + '[[include]]\nfile = "s.toml"\nargs = { fast = "fast" }\n',
        s="[arg.fast]\ndefault = true\n",
    )
    with pytest.raises(LaunchFileError) as err:
        load_launch(sub)
    assert str(err.value).endswith('is a boolean (its default: true), not a text ("fast")'), str(err.value)


def test_a_remap_onto_a_key_of_another_message_type_is_refused():
    text = SIM + '[[node]]\nname = "n"\nrun = "navigator"\nremap = { "turtle1/cmd_vel" = "turtle1/pose" }\n'
    with pytest.raises(LaunchFileError) as err:
        parse_launch(text, "f.toml")
    assert str(err.value) == (
        'f.toml: node[1] (n).remap."turtle1/cmd_vel": turtle1/cmd_vel carries turtlectl/Twist and turtle1/pose carries turtlectl/Pose: '
        "a remap joins keys of one message type"
    )
    spaced = text.replace('run = "navigator"\n', 'run = "navigator"\nnamespace = "turtle2"\n')
    with pytest.raises(
        LaunchFileError, match="turtle2/cmd_vel carries turtlectl/Twist and turtle2/pose carries turtlectl/Pose"
    ):
        parse_launch(spaced, "f.toml")
    other = text.replace('"turtle1/pose"', '"turtle3/robot/status"')
    with pytest.raises(LaunchFileError, match="turtle3/robot/status carries turtlectl/TurtleStatus"):
        parse_launch(other, "f.toml")
    fine = text.replace('"turtle1/pose"', '"turtle3/cmd_vel"')  # another turtle's commands: the same type
    assert parse_launch(fine, "f.toml").remaps["n"] == {"turtle1/cmd_vel": "turtle3/cmd_vel"}


def test_an_unused_remaps_keys_leave_out_the_internal_wildcards():
    text = SIM + '[[node]]\nname = "n"\nrun = "navigator"\nremap = { "turtle1/cmd_vell" = "x" }\n'
    with pytest.raises(LaunchFileError) as err:
        parse_launch(text, "f.toml")
    assert "@turtlectl" not in str(err.value) and "turtle1/cmd_vel," in str(err.value), str(err.value)


def test_launch_arguments_written_as_ros_positional_ones_get_a_hint(tmp_path):
    from typer.testing import CliRunner

    from turtlectl.cli.main import app
    from turtlectl.runtime.client.errors import BadInput, exit_code

    top = files(tmp_path, launch="[arg.speed]\ndefault = 1.0\n" + SIM)
    for argv in ([str(top), "speed:=2"], ["speed:=2"]):
        result = CliRunner().invoke(app, ["launch", "--check", *argv])
        assert isinstance(result.exception, BadInput) and exit_code(result.exception) == 2, result.output
        assert str(result.exception) == "speed:=2: give launch arguments as --arg speed:=2", result.exception
