"""nodes.navigator's wiring, run on a FakeNode: what it says names the keys of its own namespace."""

from __future__ import annotations

from turtlectl.messages import NavigateToRequest
from turtlectl.nodes.navigator import Navigator
from turtlectl.runtime.fake import FakeNode


def test_a_navigator_in_a_namespace_says_no_pose_on_the_key_it_waits_for():
    with FakeNode(Navigator, name="turtle2/navigator") as fake:
        goal = fake.send_goal("turtle2/navigate_to", NavigateToRequest(x=8.0, y=5.0, theta=0.0))
        fake.advance(2.0)
        assert goal.result is not None and goal.result.reason == "no pose", goal.replies
        assert goal.result.detail.startswith("no turtle2/pose for "), goal.result.detail
