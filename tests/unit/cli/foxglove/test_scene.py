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
