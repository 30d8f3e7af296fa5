"""nodes.status_monitor on a FakeNode: its answer to the world's reset names its turtle."""

from __future__ import annotations

import pytest

from turtlectl.messages import Ack, Reset
from turtlectl.nodes.status_monitor import StatusMonitor
from turtlectl.runtime.fake import FakeNode


@pytest.mark.parametrize("name, turtle", [("status_monitor", "turtle1"), ("turtle2/status_monitor", "turtle2")])
def test_a_reset_is_acknowledged_naming_the_turtle_whose_battery_is_full(name, turtle):
    with FakeNode(StatusMonitor, name=name) as fake:
        assert fake.request("reset", Reset()) == [Ack(ok=True, detail=f"{turtle}: battery full")]
