"""messages.world: the world model that crosses process boundaries is immutable, as messages are."""

import msgspec
import pytest

from turtlectl.messages.world import Limits, Obstacle, World


@pytest.mark.parametrize(
    "value, field", [(World(), "size"), (Obstacle(x=1, y=1, radius=1), "x"), (Limits(), "max_linear_speed")]
)
def test_the_world_model_is_frozen(value, field):
    """World, Obstacle and Limits travel between processes: they cannot be changed in place."""
    with pytest.raises(AttributeError):
        setattr(value, field, 2.0)
    assert msgspec.structs.replace(value, **{field: 2.0}) != value  # a new one is built instead


def test_the_world_says_what_it_contains():
    world = World(size=10.0)
    assert world.contains(0.0, 10.0) and not world.contains(-0.001, 5.0)
