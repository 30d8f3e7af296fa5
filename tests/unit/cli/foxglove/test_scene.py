"""cli.foxglove.scene: the Foxglove scene drawn from turtlectl's messages (no server needed)."""

from tests.protobuf_schemas import decoded
from turtlectl.cli.foxglove.scene import goal_entity
from turtlectl.messages import NavigateToFeedback


def _feedback(path):
    return NavigateToFeedback(
        state="driving", distance_remaining=7, heading_remaining=0, eta=2, elapsed=0, x=2, y=5, theta=0,
        goal_x=8, goal_y=5, goal_theta=90, path=path,
    )  # fmt: skip


def test_the_goal_is_drawn_with_the_path_the_navigator_follows():
    path = [(2.0, 5.0), (4.0, 6.6), (6.0, 6.6), (8.0, 5.0)]
    entity = decoded(goal_entity(_feedback(path), 1_000_000_000))
    (line,) = entity.lines
    assert [(p.x, p.y) for p in line.points] == path
    assert len(entity.arrows) == 1 and entity.arrows[0].pose.position.x == 8.0


def test_without_a_path_only_the_goal_is_drawn():
    entity = decoded(goal_entity(_feedback([]), 0))
    assert len(entity.lines) == 0 and len(entity.arrows) == 1


def _turtles(names):
    from turtlectl.messages import Turtles

    return Turtles(names=names, x=[2.0 + i for i in range(len(names))], y=[5.0] * len(names), theta=[0.0] * len(names))


def test_every_turtle_is_drawn_named_with_its_trail_and_goal():
    """Each other turtle of ``turtles`` as turtle1 is (an arrow, its name above it, its
    trail), its goal from its own navigator's feedback; one that leaves ``turtles`` is deleted."""
    from turtlectl.cli.foxglove.scene import SCENE, SceneMaker
    from turtlectl.messages import Pose
    from turtlectl.messages.world import World

    maker = SceneMaker(World(size=10.0))
    ((topic, drawn),) = maker.on_message("turtle1/pose", Pose(x=5.0, y=5.0, theta=0.0), 1)
    (turtle1, _trail1) = decoded(drawn).entities
    assert topic == SCENE and turtle1.id == "turtle" and [t.text for t in turtle1.texts] == ["turtle1"]

    assert maker.on_message("turtle2/navigate_to/feedback", _feedback([]), 2) == []  # whose? not known yet
    maker.on_message("turtles", _turtles(["turtle1", "turtle2", "turtle3"]), 2)
    moved = _turtles(["turtle1", "turtle2", "turtle3"])
    moved.x[1] = 3.5  # turtle2 (at x 3) moved half a metre
    ((_, drawn),) = maker.on_message("turtles", moved, 3)
    entities = {e.id: e for e in decoded(drawn).entities}
    assert sorted(entities) == ["trail/turtle2", "trail/turtle3", "turtle/turtle2", "turtle/turtle3"]
    assert [t.text for t in entities["turtle/turtle2"].texts] == ["turtle2"]
    assert entities["turtle/turtle2"].arrows[0].pose.position.x == 3.5
    assert [(p.x, p.y) for p in entities["trail/turtle2"].lines[0].points] == [(3.0, 5.0), (3.5, 5.0)]

    ((_, drawn),) = maker.on_message("turtle2/navigate_to/feedback", _feedback([]), 4)
    assert [e.id for e in decoded(drawn).entities] == ["goal/turtle2"]
    ((_, drawn),) = maker.on_message("navigate_to/feedback", _feedback([]), 4)
    assert [e.id for e in decoded(drawn).entities] == ["goal"]
    ((_, drawn),) = maker.on_message("lab1/navigate_to/feedback", _feedback([]), 4)  # a domain's turtle1
    assert [e.id for e in decoded(drawn).entities] == ["goal"]

    _, world = maker.world_update(5)  # a viewer connecting later sees every trail
    assert {e.id for e in decoded(world).entities} == {"world", "trail", "trail/turtle2", "trail/turtle3"}

    ((_, drawn),) = maker.on_message("turtles", _turtles(["turtle1", "turtle3"]), 6)  # turtle2 killed
    update = decoded(drawn)
    assert [d.id for d in update.deletions] == ["turtle/turtle2", "trail/turtle2", "goal/turtle2"]
    assert sorted(e.id for e in update.entities) == ["trail/turtle3", "turtle/turtle3"]
    assert maker.on_message("turtles", _turtles(["turtle1"]), 7) != []  # turtle3's deletions
    assert maker.on_message("turtles", _turtles(["turtle1"]), 8) == []  # turtle1 alone: nothing to draw


def test_a_log_record_is_foxgloves_log_for_its_log_panel():
    """Every node's records on the ``log`` channel (the bridge, record --scene)."""
    from turtlectl.cli.foxglove.scene import LOG, SceneMaker
    from turtlectl.messages import Log
    from turtlectl.messages.world import World

    levels = {}
    for level in (10, 20, 25, 30, 40, 50, 5, 0):
        record = Log(
            level=level, node="turtle2/navigator", message="m", file="/n/navigator.py", line=155, stamp=1_500_000_000
        )
        ((topic, drawn),) = SceneMaker(World()).on_message("turtlectl/log/turtle2.navigator", record, 2_000_000_000)
        assert topic == LOG == "log" and type(drawn).get_schema().name == "foxglove.Log"
        entry = decoded(drawn)
        assert (entry.name, entry.message, entry.file, entry.line) == ("turtle2/navigator", "m", "/n/navigator.py", 155)
        assert (entry.timestamp.seconds, entry.timestamp.nanos) == (1, 500_000_000)  # when it was logged
        levels[level] = entry.level
    # Foxglove's LogLevel: 0 UNKNOWN, 1 DEBUG, 2 INFO, 3 WARNING, 4 ERROR, 5 FATAL
    assert levels == {10: 1, 20: 2, 25: 2, 30: 3, 40: 4, 50: 5, 5: 1, 0: 0}
