"""The whole capstone in one specification: the ``parameters`` criterion (each node runs with the
launch file's parameters and the values the spec gives) and ``no_errors`` while goals are driven
(listed in turn, or seeded random ones clear of the walls and obstacles): parsing, the pure
comparison and goal drawing, and what ``spec from-system`` writes of them."""

from __future__ import annotations

import random
from collections import Counter
from pathlib import Path

import pytest

from turtlectl.cli.verify.document import skeleton, to_toml
from turtlectl.cli.verify.driving import Outcomes, goal_sequence, random_goal
from turtlectl.cli.verify.parameters import differences, expected_nodes, launch_file_plan
from turtlectl.cli.verify.spec import NoErrors, Parameters, SpecError, load_spec, parse_spec
from turtlectl.messages.world import Obstacle, World
from turtlectl.runtime.client.graph import Graph, NodeRow

ROOT = Path(__file__).resolve().parents[3]
CAPSTONE = ROOT / "docs" / "capstone.toml"


def test_the_capstone_spec_holds_all_six_criteria_of_the_lesson_and_its_type_once():
    spec = load_spec(CAPSTONE)
    checks = [type(c).__name__ for c in spec.criterion]
    assert checks == ["Goals", "Period", "Messages", "Parameters", "NoErrors", "ReportedTime", "RoundTrip"]
    driving = spec.criterion[4]
    assert isinstance(driving, NoErrors) and driving.random_goals and driving.minutes == 5
    # a student's copy changes one value: the status topic's type
    text = CAPSTONE.read_text()
    assert text.count('"turtlectl/TurtleStatus"') == 1 and 'type = "turtlectl/TurtleStatus"' in text
    assert "test_criteria" not in text  # nothing points into turtlectl's own tests
    renamed = parse_spec(text.replace('"turtlectl/TurtleStatus"', '"capstone_msgs/TurtleStatus"'), "copy.toml")
    assert renamed.criterion == spec.criterion and renamed.topic[0].type == "capstone_msgs/TurtleStatus"


def test_the_example_capstone_projects_spec_is_the_capstones_but_for_its_types_name():
    ours = [line for line in CAPSTONE.read_text().splitlines() if "TurtleStatus" not in line]
    example = ROOT / "examples" / "capstone" / "capstone.toml"
    theirs = [line for line in example.read_text().splitlines() if "TurtleStatus" not in line]
    assert ours == theirs
    assert load_spec(example).topic[0].type == "capstone_msgs/TurtleStatus"


def test_parameters_are_given_by_node_and_checked_as_tables():
    spec = parse_spec(
        'intent = "i"\n[[criterion]]\ncheck = "parameters"\n'
        "[criterion.params]\nnavigator = { goal_timeout = 30.0, gains = { near = 0.05 } }\n",
        "f.toml",
    )
    (c,) = spec.criterion
    assert c == Parameters(params={"navigator": {"goal_timeout": 30.0, "gains": {"near": 0.05}}})
    assert parse_spec('intent = "i"\n[[criterion]]\ncheck = "parameters"\n', "f").criterion == [Parameters()]


@pytest.mark.parametrize(
    ("text", "error"),
    [
        (
            '[[criterion]]\ncheck = "parameters"\nparams = { navigator = 3 }\n',
            "f.toml: criterion[0].params.navigator: not a table",
        ),
        (
            '[[criterion]]\ncheck = "parameters"\nparams = { navigator = {} }\n',
            "f.toml: criterion[0].params.navigator: no parameters",
        ),
        ('[[criterion]]\ncheck = "parameters"\nparam = {}\n', "did you mean params?"),
        (
            '[[criterion]]\ncheck = "no_errors"\nminutes = 1\ngoals = [[1, 1, 0]]\nrandom_goals = true\n',
            "f.toml: criterion[0]: goals and random_goals: give one of them",
        ),
        ('[[criterion]]\ncheck = "no_errors"\nminutes = 1\ngoals = [[1, 1]]\n', "f.toml: criterion[0].goals[0]"),
    ],
)
def test_a_bad_parameters_or_driving_criterion_is_one_line(text, error):
    with pytest.raises(SpecError) as caught:
        parse_spec('intent = "i"\n' + text, "f.toml")
    assert error in str(caught.value) and "\n" not in str(caught.value)


def test_a_difference_names_node_parameter_expected_and_running():
    launch = {"rate": 10.0, "gains": {"k": 1.0, "near": 0.05}, "on": True}
    running = {"rate": 5.0, "gains": {"k": 1.0, "near": 0.05}, "on": 1, "extra": "x"}
    assert differences("monitor", launch, running, "the launch file", whole=True) == [
        "monitor.rate: the launch file 10.0, running 5.0",
        "monitor.on: the launch file true, running 1",  # a flag is not a number
        'monitor.extra: running "x", the launch file has no such parameter',
    ]
    assert (
        differences("monitor", {"rate": 10, "gains": {"near": 0.05}}, running | {"rate": 10.0}, "the spec", False) == []
    )
    assert differences("monitor", {"gains": {"k": 2.0}, "rat": 1.0}, running, "the spec", whole=False) == [
        "monitor.gains.k: the spec 2.0, running 1.0",
        "monitor.rat: the spec 1.0, the node has no such parameter; did you mean rate?",
    ]


def test_the_launch_file_is_read_as_launch_reads_it_with_its_time_scale():
    plan = launch_file_plan(ROOT / "launch.toml", time_scale=5.0)
    nodes = expected_nodes(plan)
    assert set(nodes) == {"sim", "navigator", "status_monitor", "obstacle_detector"}
    assert nodes["sim"][0] == "sim" and nodes["sim"][1]["real_time_factor"] == 5.0
    assert nodes["navigator"][1]["goal_timeout"] == 30.0  # defaults filled in


def test_random_goals_are_seeded_inside_the_world_and_clear_of_its_obstacles():
    world = World(size=11.0, obstacles=[Obstacle(x=5.0, y=5.0, radius=2.0), Obstacle(x=8.0, y=2.0, radius=1.0)])
    c = NoErrors(minutes=1, random_goals=True, seed=7)
    first = [g for g, _ in zip(goal_sequence(c, world), range(200), strict=False)]
    assert first == [
        g for g, _ in zip(goal_sequence(c, world), range(200), strict=False)
    ]  # the same seed: the same goals
    assert len(set(first)) > 150
    for x, y, theta in first:
        assert 1.0 <= x <= 10.0 and 1.0 <= y <= 10.0 and -180.0 <= theta <= 180.0
        assert all(((x - o.x) ** 2 + (y - o.y) ** 2) ** 0.5 >= o.radius + 1.0 for o in world.obstacles)
    with pytest.raises(ValueError, match="no goal 1 m clear"):
        random_goal(random.Random(0), World(size=3.0, obstacles=[Obstacle(x=1.5, y=1.5, radius=1.0)]))


def test_listed_goals_are_driven_in_turn_over_again_and_none_without_goals():
    c = NoErrors(minutes=1, goals=[(1.0, 2.0, 0.0), (3.0, 4.0, 90.0)])
    assert [g for g, _ in zip(goal_sequence(c, World()), range(5), strict=False)] == [
        (1.0, 2.0, 0.0),
        (3.0, 4.0, 90.0),
        (1.0, 2.0, 0.0),
        (3.0, 4.0, 90.0),
        (1.0, 2.0, 0.0),
    ]
    assert list(goal_sequence(NoErrors(minutes=1), World())) == []


def test_the_outcomes_say_how_many_goals_ended_how_and_only_errors_fail():
    out = Outcomes()
    out.reached, out.canceled = 10, 1
    out.unreached = Counter({"blocked": 2, "refused": 1})
    assert out.summary() == "14 goals driven: 10 reached, 3 not reached (blocked 2, refused 1), 1 canceled at the end"
    assert out.problems() == []
    out.erred = [f"({i}, 1, 0): no answer" for i in range(5)]
    assert out.problems() == [
        "goal (0, 1, 0): no answer",
        "goal (1, 1, 0): no answer",
        "goal (2, 1, 0): no answer",
        "and 2 more",
    ]
    assert out.summary().endswith("5 erred")


def test_the_skeleton_states_each_nodes_parameters_and_reads_them_back():
    graph = Graph(
        nodes=[NodeRow("sim", 1, "h", 1.0), NodeRow("turtle2/navigator", 2, "h", 1.0)], topics=[], services=[]
    )
    params = {
        "sim": {"x": 5.5, "turtles": [], "hint": None},
        "turtle2/navigator": {"goal_timeout": 30.0, "gains": {"near": 0.05}},
        "quiet": {},
    }
    spec = skeleton(graph, {}, params)
    assert spec.criterion == [
        Parameters(params={"sim": {"x": 5.5, "turtles": []}, "turtle2/navigator": params["turtle2/navigator"]})
    ]
    text = to_toml(spec)
    assert '[criterion.params."turtle2/navigator"]\ngoal_timeout = 30.0\ngains = { "near" = 0.05 }\n' in text
    assert parse_spec(text, "skeleton") == spec
