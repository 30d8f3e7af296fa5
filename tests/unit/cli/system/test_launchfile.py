"""Launch-file validation: every mistake names the file and the exact key path."""

from pathlib import Path

import msgspec
import pytest

from turtlectl.cli.system.launchfile import (
    PACKAGED_LAUNCH,
    LaunchFileError,
    load_launch,
    parse_launch,
)
from turtlectl.cli.system.overrides import node_config, parse_assignment, select_nodes, with_overrides

ROOT = Path(__file__).resolve().parents[4]

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


def test_use_sim_time_puts_every_node_of_a_system_without_simulator_on_the_clock_key():
    """`launch --exclude sim --use-sim-time`: a system a replay (`play --clock`) drives; each node
    follows the clock, the simulator's speed untouched when it runs."""
    from turtlectl.cli.system.overrides import launch_plan
    from turtlectl.cli.tools.format import plan_notes

    plan = launch_plan(ROOT / "launch.toml", [], ["sim"], [], use_sim_time=True)
    assert [e.name for e in plan.launch.node] == ["navigator", "status_monitor", "obstacle_detector"]
    assert all(e.use_sim_time for e in plan.launch.node)
    assert node_config(plan, "status_monitor", "tcp/127.0.0.1:7447").use_sim_time
    assert plan_notes(plan)  # --check and the launch say the nodes follow the clock
    whole = launch_plan(ROOT / "launch.toml", [], [], [], use_sim_time=True)
    assert all(e.use_sim_time for e in whole.launch.node)
    assert whole.params["sim"].get("real_time_factor", 1.0) == 1.0  # the simulator's pace untouched


@pytest.mark.parametrize(
    "text, message",
    [
        (MINIMAL + "colour = 1\n", "f.toml: node[0] (sim).colour: unknown key"),
        (MINIMAL + "[node.params]\nx = 'left'\n", "f.toml: node[0] (sim).params.x must be a number"),
        (
            MINIMAL + "[node.params]\ncmd_timeout = -1\n",
            "f.toml: node[0] (sim).params.cmd_timeout must be >= 0.05",
        ),
        (MINIMAL + "[node.params]\nspeed = 3\n", "f.toml: node[0] (sim).params.speed: unknown key"),
        (MINIMAL + "respawn = 'yes'\n", "f.toml: node[0] (sim).respawn must be true or false"),
        ("[world]\nsize = 0\n" + MINIMAL, "f.toml: world.size must be > 0"),
        (
            "[world]\nobstacles = [{x = 1, y = 1}]\n" + MINIMAL,
            "f.toml: world.obstacles[0].radius: missing required key",
        ),
        ("[limits]\nmax_linear_speed = 'fast'\n" + MINIMAL, "f.toml: limits.max_linear_speed must be a number"),
        ('[[node]]\nname = "a"\n', "f.toml: node[0] (a): neither run nor cmd: give run (a node kind or class)"),
        ('[[node]]\nname = "a"\nrun = "turtle"\n', "f.toml: node[0] (a).run: unknown node kind 'turtle'"),
        (MINIMAL + MINIMAL, "f.toml: node[1] (sim).name: duplicate node name 'sim'"),
        ('[[node]]\nname = "a/b"\nrun = "sim"\n', "f.toml: node[0] (a/b).name: 'a/b' is not a valid name"),
        ("", "f.toml: node: the launch file lists no node"),  # nor any [[group]]
        ("node = []\n", "f.toml: node: the launch file lists no node"),
        ("[[node]\n", "f.toml: not valid TOML"),
        (
            '[[node]]\nname = "n"\nrun = "navigator"\n[node.params.gains]\nk_linear = "x"\n',
            "f.toml: node[0] (n).params.gains.k_linear must be a number",
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


NAV = '[[node]]\nname = "navigator"\nrun = "navigator"\n'
STATUS = '[[node]]\nname = "status_monitor"\nrun = "status_monitor"\n'
DETECTOR = '[[node]]\nname = "obstacle_detector"\nrun = "obstacle_detector"\n'


@pytest.mark.parametrize(
    "text, message",
    [
        # the spawn: the simulator itself would only clamp it to the walls, or leave the turtle stuck
        (
            MINIMAL + "[node.params]\nx = 12.0\n",
            "f.toml: node[0] (sim).params.x: spawn x = 12 m is outside the world (0 to 11.0889 m)",
        ),
        (
            MINIMAL + "[node.params]\ny = -0.5\n",
            "f.toml: node[0] (sim).params.y: spawn y = -0.5 m is outside the world",
        ),
        (
            "[world]\nsize = 5\n" + MINIMAL,
            "f.toml: node[0] (sim).params.x: spawn x = 5.54444 m is outside the world (0 to 5 m)",
        ),
        (
            "[world]\nobstacles = [{x = 1, y = 1, radius = 0.2}, {x = 5.5, y = 5.6, radius = 0.5}]\n" + MINIMAL,
            "f.toml: node[0] (sim).params: spawn (5.54444, 5.54444) is inside world.obstacles[1] (centre (5.5, 5.6), radius 0.5 m)",
        ),
        # obstacles that cover the world, or are not in it
        (
            "[world]\nobstacles = [{x = 1, y = 1, radius = 0.2}, {x = 5, y = 5, radius = 9}]\n" + MINIMAL,
            "f.toml: world.obstacles[1]: covers the whole world (centre (5, 5), radius 9 m; the world is 11.0889 m square)",
        ),
        (
            "[world]\nobstacles = [{x = 20, y = 5, radius = 1}]\n" + MINIMAL,
            "f.toml: world.obstacles[0]: centre (20, 5), radius 1 m lies entirely outside the world (0 to 11.0889 m)",
        ),
        # rates and times within sane ranges (a node at 1e9 Hz spins a CPU)
        (
            STATUS + "[node.params]\nrate = 1e9\n",
            "f.toml: node[0] (status_monitor).params.rate must be <= 100",
        ),
        (
            STATUS + "[node.params]\nrate = 0.0\n",
            "f.toml: node[0] (status_monitor).params.rate must be >= 0.1",
        ),
        (
            NAV + "[node.params]\nfeedback_rate = 1e9\n",
            "f.toml: node[0] (navigator).params.feedback_rate must be <= 100",
        ),
        (
            DETECTOR + "[node.params]\nrate = 1000\n",
            "f.toml: node[0] (obstacle_detector).params.rate must be <= 100",
        ),
        (
            DETECTOR + "[node.params]\nbeams = 100000\n",
            "f.toml: node[0] (obstacle_detector).params.beams must be <= 3600",
        ),
        (
            DETECTOR + "[node.params]\nphantom_rate = 1e6\n",
            "f.toml: node[0] (obstacle_detector).params.phantom_rate must be <= 100",
        ),
        (
            NAV + "[node.params]\ngoal_timeout = 1e9\n",
            "f.toml: node[0] (navigator).params.goal_timeout must be <= 3600",
        ),
        (
            NAV + "[node.params]\npose_timeout = 0.001\n",
            "f.toml: node[0] (navigator).params.pose_timeout must be >= 0.05",
        ),
        (
            MINIMAL + "[node.params]\ncmd_timeout = 1e9\n",
            "f.toml: node[0] (sim).params.cmd_timeout must be <= 60",
        ),
        (
            "[supervisor]\nsigint_timeout = 1e9\n" + MINIMAL,
            "f.toml: supervisor.sigint_timeout must be <= 60",
        ),
        (
            MINIMAL + "respawn = true\nrespawn_delay = 1e9\n",
            "f.toml: node[0] (sim).respawn_delay must be <= 3600",
        ),
        ("[supervisor]\nkeep_logs = -1\n" + MINIMAL, "f.toml: supervisor.keep_logs must be >= 0"),
        # one node of each kind: the keys are fixed
        (
            MINIMAL + '[[node]]\nname = "sim2"\nrun = "sim"\n',
            "f.toml: node[1] (sim2).run: a second 'sim' node (node[0] (sim) is one): both would publish turtle1/pose",
        ),
        (NAV + NAV.replace('"navigator"\nrun', '"nav2"\nrun'), "f.toml: node[1] (nav2).run: a second 'navigator' node"),
        # the navigator must not forget obstacles between two scans
        (
            NAV + "[node.params]\nscan_timeout = 0.1\n" + DETECTOR,
            "f.toml: node[0] (navigator).params.scan_timeout: 0.1 s is not longer than the scan period of "
            "obstacle_detector (0.2 s at 5 Hz)",
        ),
        # the nearest valid name
        (
            NAV + "[node.params]\ngoal_timeot = 60\n",
            "f.toml: node[0] (navigator).params.goal_timeot: unknown key; did you mean goal_timeout?",
        ),
        (
            NAV + "[node.params.gains]\nk_linaer = 1\n",
            "f.toml: node[0] (navigator).params.gains.k_linaer: unknown key; did you mean k_linear?",
        ),
        ("[wrold]\nsize = 5\n" + MINIMAL, "f.toml: wrold: unknown key; did you mean world?"),
        ("[world]\nsise = 5\n" + MINIMAL, "f.toml: world.sise: unknown key; did you mean size?"),
        (MINIMAL + "respwn = true\n", "f.toml: node[0] (sim).respwn: unknown key; did you mean respawn?"),
        (
            '[[node]]\nname = "a"\nrun = "navigatr"\n',
            "f.toml: node[0] (a).run: unknown node kind 'navigatr'; did you mean navigator?",
        ),
        ('[[node]]\nname = "world"\nrun = "sim"\n', "f.toml: node[0] (world).name: 'world' is reserved"),
        (  # a value a Literal does not allow: the allowed ones named, not msgspec's "Invalid enum value"
            '[[node]]\nname = "b"\nrun = "ros2_bridge"\n[[node.params.topics]]\nkey = "chatter"\nros = "/chatter"\n'
            'type = "std_msgs/msg/String"\ndirection = "from-ros"\n',
            'f.toml: node[0] (b).params.topics[0].direction must be one of both, from_ros, to_ros (got "from-ros")',
        ),
    ],
)
def test_files_that_cannot_work_are_refused_before_anything_starts(text, message):
    with pytest.raises(LaunchFileError) as err:
        parse_launch(text, source="f.toml")
    assert str(err.value).startswith(message), str(err.value)


def test_edge_cases_that_work_are_accepted():
    # spawn on the wall, an obstacle partly outside the world, the highest rates
    plan = parse_launch(
        "[world]\nobstacles = [{x = -0.5, y = 5, radius = 1}]\n"
        + MINIMAL
        + "[node.params]\nx = 0.0\ny = 11.08\n"
        + STATUS
        + "[node.params]\nrate = 100.0\n"
        + NAV
        + "[node.params]\nscan_timeout = 0.25\nfeedback_rate = 100\n"
        + DETECTOR
        + "[node.params]\nrate = 5\nbeams = 3600\n"
    )
    assert plan.params["sim"]["x"] == 0.0 and plan.params["status_monitor"]["rate"] == 100.0
    assert plan.launch.supervisor.keep_logs == 20


def test_the_default_launch_file_documents_every_bound():
    text = (ROOT / "launch.toml").read_text()
    for words in ("0.1 to 100", "0.05 to 60", "0.1 to 3600", "1 to 3600", "keep_logs"):
        assert words in text, words


SET = "NODE.PARAM=VALUE"


def override(*items: str, plan=None):
    plan = plan or load_launch(ROOT / "launch.toml")
    return with_overrides(plan, [parse_assignment(item, "--set", SET) for item in items], "--set")


def test_set_takes_spaces_tables_and_nested_keys():
    plan = load_launch(ROOT / "launch.toml")
    out = override(
        "navigator.goal_timeout = 60",
        " navigator.gains.k_linear=25 ",
        "world.size=20",
        "limits.max_linear_speed = 2",
        "supervisor.keep_logs=3",
        plan=plan,
    )
    assert out.params["navigator"]["goal_timeout"] == 60.0 and out.params["navigator"]["gains"]["k_linear"] == 25.0
    assert out.launch.world.size == 20.0 and len(out.launch.world.obstacles) == 3
    assert out.launch.limits.max_linear_speed == 2.0 and out.launch.supervisor.keep_logs == 3
    assert out.source == plan.source
    assert plan.params["navigator"]["goal_timeout"] == 30.0 and plan.launch.world.size < 12  # unchanged
    assert override("world.obstacles = []").launch.world.obstacles == []
    assert override("world.obstacles = [{x = 1, y = 1, radius = 0.5}]").launch.world.obstacles[0].radius == 0.5


@pytest.mark.parametrize(
    "item, message",
    [
        ("navigator.goal_timeot=60", "--set navigator.goal_timeot: unknown key; did you mean goal_timeout?"),
        ("navigator.goal_timeout=-1", "--set navigator.goal_timeout must be >= 0.1"),
        ("navigator.goal_timeout=soon", "--set navigator.goal_timeout must be a number"),
        ("navigator.gains.k_linaer=1", "--set navigator.gains.k_linaer: unknown key; did you mean k_linear?"),
        ("status_monitor.rate=1e9", "--set status_monitor.rate must be <= 100"),
        ("world.size=-3", "--set world.size must be > 0"),
        ("world.sise=3", "--set world.sise: unknown key; did you mean size?"),
        (
            "world.size=5",
            "--set world.obstacles[0]: centre (2, 9), radius 0.5 m lies entirely outside the world (0 to 5 m)",
        ),
        ("limits.max_linear_sped=3", "--set limits.max_linear_sped: unknown key; did you mean max_linear_speed?"),
        (
            "navigatr.goal_timeout=60",
            "--set 'navigatr.goal_timeout=60': no node or table named 'navigatr'; did you mean navigator?",
        ),
        ("navigator.goal_timeout", "--set 'navigator.goal_timeout': write it as NODE.PARAM=VALUE"),
        ("navigator..x=1", "--set 'navigator..x=1': write it as"),
        ("world=5", "--set 'world=5': name a key of world"),
        ("navigator.goal_timeout.x=1", "--set navigator.goal_timeout: is not a table"),
    ],
)
def test_set_errors_name_the_node_and_the_nearest_key(item, message):
    with pytest.raises(LaunchFileError) as err:
        override(item)
    assert str(err.value).startswith(message), str(err.value)


def test_set_world_size_checks_the_spawn_again():
    with pytest.raises(LaunchFileError) as err:
        override("world.obstacles = []", "world.size=5")
    assert str(err.value) == "--set sim.x: spawn x = 5.54444 m is outside the world (0 to 5 m)"


def test_set_values_are_toml_or_else_text():
    assignment = parse_assignment("a.b = plain text", "--set", SET)
    assert assignment.keys == ("a", "b") and assignment.value == "plain text"
    assert parse_assignment("a.b=[1, 2]", "--set", SET).value == [1, 2]
    assert parse_assignment("a.b='quoted'", "--set", SET).value == "quoted"
    assert parse_assignment("a.b=true", "--set", SET).value is True


def test_run_param_overrides_are_validated_as_the_file_is():
    plan = load_launch(ROOT / "launch.toml")
    config = node_config(plan, "navigator", "tcp/127.0.0.1:7447", ["goal_timeout = 60", "gains.k_linear=25"])
    assert config.params["goal_timeout"] == 60.0 and config.params["gains"]["k_linear"] == 25.0
    assert config.world == plan.launch.world
    with pytest.raises(LaunchFileError) as err:
        node_config(plan, "navigator", "tcp/127.0.0.1:7447", ["goal_timeot=60"])
    assert str(err.value) == "--param navigator.goal_timeot: unknown key; did you mean goal_timeout?"
    with pytest.raises(LaunchFileError, match=r"--param sim.x: spawn x = 20 m is outside the world"):
        node_config(plan, "sim", "tcp/127.0.0.1:7447", ["x=20"])
    with pytest.raises(LaunchFileError, match=r"no node named 'navigatr'; did you mean navigator\?"):
        node_config(plan, "navigatr", "tcp/127.0.0.1:7447")


def test_only_and_exclude_suggest_the_nearest_node():
    plan = load_launch(ROOT / "launch.toml")
    with pytest.raises(LaunchFileError, match=r"--only navigatr: no node named 'navigatr'; did you mean navigator\?"):
        select_nodes(plan, ["navigatr"], [])
    assert [e.name for e in select_nodes(plan, [], ["obstacle_detector"]).launch.node] == [
        "sim",
        "navigator",
        "status_monitor",
    ]


def _running(scan_timeout: float = 1.0, rate: float = 5.0) -> dict:
    from turtlectl.nodes.params import NavigatorParams, ObstacleDetectorParams, StatusMonitorParams

    def table(struct, **changes):
        return {**msgspec.to_builtins(struct), **changes}

    return {
        "navigator": ("navigator", table(NavigatorParams(), scan_timeout=scan_timeout)),
        "obstacle_detector": ("obstacle_detector", table(ObstacleDetectorParams(), rate=rate)),
        "status_monitor": ("status_monitor", table(StatusMonitorParams())),
    }


def test_a_change_is_validated_against_what_runs_as_launch_set_validates_a_file():
    """`param set` refuses what the launch file refuses, naming the rule it would break."""
    from turtlectl.cli.system.overrides import running_change
    from turtlectl.messages.world import World

    assert running_change(_running(), World(), "navigator", "goal_timeout", "60", "param set") == 60.0
    with pytest.raises(
        LaunchFileError, match=r"^param set navigator.goal_timeot: unknown key; did you mean goal_timeout\?$"
    ):
        running_change(_running(), World(), "navigator", "goal_timeot", "60", "param set")
    with pytest.raises(LaunchFileError) as broke:
        running_change(_running(), World(), "obstacle_detector", "rate", "0.5", "param set")
    assert str(broke.value).startswith(
        "param set obstacle_detector.rate = 0.5: it would break a rule of the running system: navigator.scan_timeout: "
        "1 s is not longer than the scan period of obstacle_detector (2 s at 0.5 Hz)"
    )


def test_a_system_that_already_breaks_a_rule_still_takes_changes_that_do_not_break_it_further():
    """The navigator respawned with its launch file's scan_timeout (1 s) after the detector was
    slowed to 0.8 Hz under a longer one: `param set` still takes what does not make it worse."""
    from turtlectl.cli.system.overrides import running_change
    from turtlectl.messages.world import World

    broken = _running(scan_timeout=1.0, rate=0.8)
    assert running_change(broken, World(), "status_monitor", "rate", "5", "param set") == 5.0
    assert running_change(broken, World(), "obstacle_detector", "rate", "5", "param set") == 5.0  # the repair
    assert running_change(broken, World(), "navigator", "scan_timeout", "2", "param set") == 2.0  # the other one
    with pytest.raises(LaunchFileError, match="2 s at 0.5 Hz"):  # worse: refused
        running_change(broken, World(), "obstacle_detector", "rate", "0.5", "param set")


def test_a_mistake_in_the_value_itself_is_named_as_such_not_as_a_broken_rule():
    """A list item's missing key is named, not "it would break a rule of the running system"."""
    from turtlectl.cli.system.overrides import running_change
    from turtlectl.messages.world import World

    with pytest.raises(LaunchFileError) as err:
        running_change(
            _running(), World(), "obstacle_detector", "undeclared_obstacles", "[{x = 5, y = 5}]", "param set"
        )
    assert str(err.value) == "param set obstacle_detector.undeclared_obstacles[0].radius: missing required key"


# -- namespaces -----------------------------------------------------------------
FLEET = """
[[node]]
name = "sim"
run = "sim"
[node.params]
turtles = [{ name = "turtle2", x = 2.0, y = 2.0 }]

[[node]]
name = "navigator"
run = "navigator"

[[group]]
namespace = "turtle2"
[[group.node]]
name = "navigator"
run = "navigator"
[group.node.params]
goal_timeout = 60.0
[[group.node]]
name = "status_monitor"
run = "status_monitor"
"""


def test_a_groups_nodes_are_named_and_keyed_in_its_namespace():
    from turtlectl.cli.system.overrides import node_config

    plan = parse_launch(FLEET, source="f.toml")
    assert [e.name for e in plan.launch.node] == ["sim", "navigator", "turtle2/navigator", "turtle2/status_monitor"]
    assert plan.params["turtle2/navigator"]["goal_timeout"] == 60.0 and plan.params["navigator"]["goal_timeout"] == 30.0
    config = node_config(plan, "turtle2/navigator", "tcp/127.0.0.1:1")
    assert [c.key for c in config.claims] == ["turtle2/navigate_to"]
    assert config.interface is not None
    assert set(config.interface.serves) == {"turtle2/navigate_to", "turtle2/navigate_to/cancel", "turtle2/moving"}
    assert "turtle2/pose" in config.interface.subscribes and "turtles" in config.interface.subscribes
    assert config.interface.publishes[0] == "turtle2/cmd_vel"


def test_a_node_may_name_its_own_namespace_which_is_one_turtles():
    text = FLEET + '\n[[node]]\nname = "nav"\nrun = "navigator"\nnamespace = "turtle3"\n'
    assert "turtle3/nav" in [e.name for e in parse_launch(text, source="f.toml").launch.node]
    nested = FLEET + '\n[[group]]\nnamespace = "lab"\n[[group.node]]\nname = "nav"\nrun = "navigator"\n'
    nested += 'namespace = "turtle3"\n'
    with pytest.raises(LaunchFileError, match=r"group\[1\]\.node\[0\] \(nav\)\.namespace: the node is in its group's"):
        parse_launch(nested, source="f.toml")


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (
            '[[group]]\nnamespace = "turtle2"\n[[group.node]]\nname = "nav2"\nrun = "navigator"\n',
            "f.toml: group[1].node[0] (turtle2/nav2).run: a second 'navigator' node in namespace 'turtle2' "
            "(group[0].node[0] (turtle2/navigator) is one): both would serve turtle2/navigate_to",
        ),
        (
            '[[group]]\nnamespace = "turtle2"\n[[group.node]]\nname = "navigator"\nrun = "status_monitor"\n',
            "f.toml: group[1].node[0] (turtle2/navigator).name: duplicate node name 'turtle2/navigator'",
        ),
        ('[[group]]\nnamespace = "a b"\n', "f.toml: group[1].namespace: 'a b' is not a namespace"),
        (
            '[[group]]\nnamespace = "robot"\n',
            "f.toml: group[1].namespace: 'robot' is the first part of the system's own keys",
        ),
        (
            '[[group]]\nnamespace = "a/b"\n',
            "f.toml: group[1].namespace: 'a/b' is not a namespace: the name of the turtle",
        ),
        (
            '[[group]]\nnamespace = "turtle1"\n[[group.node]]\nname = "navigator"\nrun = "navigator"\n',
            "f.toml: group[1].node[0] (turtle1/navigator).namespace: a second 'navigator' node driving turtle1 "
            "(node[1] (navigator) runs outside any namespace, which is turtle1's too)",
        ),
        (
            '[[group]]\nnamespace = "t9"\n[[group.node]]\nname = "sim2"\nrun = "sim"\n',
            "f.toml: group[1].node[0] (t9/sim2).namespace: the simulator serves every turtle of the world",
        ),
        (
            '[[group]]\nnamespace = "t9"\n[[group.node]]\nname = "a/b"\nrun = "navigator"\n',
            "f.toml: group[1].node[0] (a/b).name: 'a/b' is not a valid name",
        ),
    ],
)
def test_namespace_mistakes_name_the_group_and_node(extra, message):
    with pytest.raises(LaunchFileError) as err:
        parse_launch(FLEET + "\n" + extra, source="f.toml")
    assert str(err.value).startswith(message), str(err.value)


@pytest.mark.parametrize(
    ("turtles", "message"),
    [
        ('[{ name = "turtle2", x = 5.5, y = 5.6 }]', "params.turtles[0]: (5.5, 5.6) is 0.10 m from turtle1"),
        ('[{ name = "turtle1", x = 2.0, y = 2.0 }]', "params.turtles[0]: a turtle named turtle1 exists"),
        (
            '[{ name = "spawn", x = 2.0, y = 2.0 }]',
            "params.turtles[0]: 'spawn' is the first part of the system's own keys",
        ),
        ('[{ name = "b", x = 20.0, y = 2.0 }]', "params.turtles[0]: (20, 2) is outside the world"),
    ],
)
def test_the_simulators_turtles_at_start_are_placed_as_a_spawn_would_be(turtles, message):
    text = f'[[node]]\nname = "sim"\nrun = "sim"\n[node.params]\ny = 5.6\nx = 5.5\nturtles = {turtles}\n'
    text = text.replace("y = 5.6\n", "y = 5.5\n")
    with pytest.raises(LaunchFileError) as err:
        parse_launch(text, source="f.toml")
    assert message in str(err.value), str(err.value)


def test_the_fleet_example_validates():
    from pathlib import Path

    plan = parse_launch((Path(__file__).parents[4] / "examples" / "fleet" / "launch.toml").read_text(), source="fleet")
    assert len(plan.launch.node) == 10


def test_a_change_to_a_namespaced_node_is_validated_against_its_own_namespace():
    """`param set turtle2/obstacle_detector rate 0.5` that breaks turtle2's navigator's scan_timeout
    is noticed: the running system's data names turtle2's nodes with their namespace (without it
    every check would fail the same before and after, so none would count)."""
    from turtlectl.cli.system.overrides import running_change
    from turtlectl.messages.world import World

    fleet = _running() | {f"turtle2/{name}": kind_params for name, kind_params in _running().items()}
    with pytest.raises(LaunchFileError) as broke:
        running_change(fleet, World(), "turtle2/obstacle_detector", "rate", "0.5", "param set")
    assert str(broke.value).startswith(
        "param set turtle2/obstacle_detector.rate = 0.5: it would break a rule of the running system: "
        "turtle2/navigator.scan_timeout: 1 s is not longer than the scan period of turtle2/obstacle_detector"
    ), str(broke.value)
    assert running_change(fleet, World(), "turtle2/navigator", "goal_timeout", "50", "param set") == 50.0


def test_a_ros_namespace_may_be_written_with_its_slash_and_a_turtle_missing_at_start_is_noted():
    """`namespace = "/turtle2"` (as PushRosNamespace is written) is taken; a namespace whose turtle
    the simulator does not make gets a note from --check."""
    from turtlectl.cli.tools.format import plan_notes, plan_text

    plan = parse_launch(FLEET.replace('namespace = "turtle2"', 'namespace = "/turtle2"'), source="f.toml")
    assert "turtle2/navigator" in [e.name for e in plan.launch.node] and plan_notes(plan) == []
    lonely = parse_launch(FLEET.replace('namespace = "turtle2"', 'namespace = "turtle9"'), source="f.toml")
    assert plan_notes(lonely) == [
        "no turtle turtle9 at start for the nodes of namespace turtle9: add it to sim's params.turtles, "
        "or spawn it (turtlectl spawn X Y THETA --name turtle9)"
    ]
    assert plan_text(lonely).endswith("note: " + plan_notes(lonely)[0])


def test_time_scale_puts_every_node_on_the_simulators_clock_and_check_says_so():
    """`launch --time-scale 5` is the simulator's real_time_factor and every node's
    use_sim_time (not a cmd program's); --check and the launch say it, the simulator as the one
    that makes the clock (`sim (...; use_sim_time)` would confuse)."""
    from turtlectl.cli.system.overrides import launch_plan
    from turtlectl.cli.tools.format import plan_notes, plan_text

    plan = launch_plan(ROOT / "launch.toml", [], [], [], 5.0)
    assert plan.params["sim"]["real_time_factor"] == 5.0
    assert all(e.use_sim_time for e in plan.launch.node)
    assert node_config(plan, "navigator", "tcp/127.0.0.1:7447").use_sim_time
    text = plan_text(plan)
    assert "sim (run sim; required; makes the clock, 5x real time)" in text
    assert "; use_sim_time)" in text.split("navigator (")[1].split("\n")[0]
    assert (
        plan_notes(plan)[0]
        == "simulated time: sim runs 5x as fast as the wall clock; every node follows its clock (use_sim_time)"
    )
    alone = launch_plan(ROOT / "launch.toml", [], [], ["sim.real_time_factor=2"])
    assert not any(e.use_sim_time for e in alone.launch.node)
    assert "navigator, status_monitor, obstacle_detector keep the wall clock" in plan_notes(alone)[0]
    assert plan_notes(launch_plan(ROOT / "launch.toml", [], [], [])) == []
    with pytest.raises(LaunchFileError, match="real_time_factor"):
        launch_plan(ROOT / "launch.toml", [], [], [], 50.0)


@pytest.mark.parametrize(
    "text, message",
    [
        (
            '[[node]]\nname = "navigator"\nrun = "navigator"\nparams = { goal_timeout = "fast" }\n',
            'f.toml: node[0] (navigator).params.goal_timeout must be a number (got "fast")',
        ),
        (
            MINIMAL + "[node.params]\ncmd_timeout = 0.01\n",
            "f.toml: node[0] (sim).params.cmd_timeout must be >= 0.05 (got 0.01)",
        ),
        (MINIMAL + "respawn = 'yes'\n", 'f.toml: node[0] (sim).respawn must be true or false (got "yes")'),
        (MINIMAL + "respawn_max = 1.5\n", "f.toml: node[0] (sim).respawn_max must be a whole number (got 1.5)"),
    ],
)
def test_a_value_of_the_wrong_type_or_range_reads_as_param_set_says_it(text, message):
    """A launch file said ``Expected `float`, got `str` `` where `param set` says
    ``goal_timeout must be a number (got "fast")``: one wording, in the user's terms."""
    with pytest.raises(LaunchFileError) as err:
        parse_launch(text, source="f.toml")
    assert str(err.value) == message


def test_check_says_how_many_failed_starts_end_a_respawning_nodes_tries():
    """A node that fails before it is ready is given up on after start_tries starts, not after
    respawn_max: --check says both limits."""
    from turtlectl.cli.tools.format import plan_text

    respawning = FLEET.replace('run = "navigator"\n', 'run = "navigator"\nrespawn = true\n', 1)
    text = plan_text(parse_launch(respawning, source="f.toml"))
    assert "at most 5 in a row; 3 failed starts in a row and no more" in text, text


FLEET_EXAMPLE = ROOT / "examples" / "fleet" / "launch.toml"
KINDS = ("navigator", "status_monitor", "obstacle_detector")

SYMMETRIC = """
[[node]]
name = "sim"
run = "sim"
[node.params]
turtles = [{ name = "turtle2", x = 2.0, y = 2.0 }]

[[group]]
namespace = "turtle1"
[[group.node]]
name = "navigator"
run = "navigator"
[[group.node]]
name = "status_monitor"
run = "status_monitor"

[[group]]
namespace = "turtle2"
[[group.node]]
name = "navigator"
run = "navigator"
[group.node.params]
goal_timeout = 45.0
[[group.node]]
name = "status_monitor"
run = "status_monitor"
"""


def test_turtle1_lives_in_a_namespace_as_any_turtle():
    from turtlectl.cli.system.overrides import node_config

    plan = parse_launch(SYMMETRIC, source="f.toml")
    assert [e.name for e in plan.launch.node] == [
        "sim",
        "turtle1/navigator",
        "turtle1/status_monitor",
        "turtle2/navigator",
        "turtle2/status_monitor",
    ]
    from turtlectl.cli.tools.format import plan_notes

    config = node_config(plan, "turtle1/navigator", "tcp/127.0.0.1:7447")
    keys = {k for f in config.interface.__struct_fields__ for k in getattr(config.interface, f)}
    assert "turtle1/navigate_to" in keys and "turtle1/pose" in keys and "navigate_to" not in keys
    assert plan_notes(plan) == []  # turtle1 is made by the simulator: no note about a missing turtle


def test_only_and_exclude_take_turtles_namespaces_and_globs():
    fleet = parse_launch(FLEET_EXAMPLE.read_text(), source=str(FLEET_EXAMPLE))
    names = lambda plan: [e.name for e in plan.launch.node]  # noqa: E731
    assert names(select_nodes(fleet, ["turtle1"], [])) == ["navigator", "status_monitor", "obstacle_detector"]
    assert names(select_nodes(fleet, ["sim", "turtle1"], [])) == [
        "sim",
        "navigator",
        "status_monitor",
        "obstacle_detector",
    ]
    assert names(select_nodes(fleet, ["turtle2/*"], [])) == [f"turtle2/{k}" for k in KINDS]
    assert names(select_nodes(fleet, ["*/navigator"], [])) == ["turtle2/navigator", "turtle3/navigator"]
    assert "sim" in names(select_nodes(fleet, [], ["turtle1"]))
    assert names(select_nodes(fleet, [], ["turtle1", "turtle3", "/turtle2"])) == ["sim"]
    with pytest.raises(LaunchFileError, match=r"--only turtle9: no node named 'turtle9'"):
        select_nodes(fleet, ["turtle9"], [])
    with pytest.raises(LaunchFileError, match=r"--exclude nav\*x: no node named 'nav\*x'"):
        select_nodes(fleet, [], ["nav*x"])
    symmetric = parse_launch(SYMMETRIC, source="f.toml")
    assert names(select_nodes(symmetric, ["turtle1"], [])) == ["turtle1/navigator", "turtle1/status_monitor"]


def test_the_run_key_s_reference_names_every_built_in_kind():
    """docs/reference/launch-file.md is generated from the Struct's comments: a new built-in kind
    in nodes/kinds.py KINDS must be named there too."""
    import inspect

    from turtlectl.cli.system import launchfile
    from turtlectl.nodes.kinds import KINDS

    run = next(line for line in inspect.getsource(launchfile).splitlines() if line.strip().startswith("run: str"))
    assert [kind for kind in KINDS if kind not in run] == []
