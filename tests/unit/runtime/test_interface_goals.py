"""An Interface declares a goal service once (``goals=("navigate_to",)``): it stands for all its
server declares, in the node's runtime check and in the router's rules alike (roles.interface_of)."""

from __future__ import annotations

import msgspec

from turtlectl.cli.system.access import launch_goal_services
from turtlectl.messages import NavigateToFeedback, NavigateToRequest, NavigateToResponse
from turtlectl.nodes.kinds import KINDS
from turtlectl.runtime.config import Interface
from turtlectl.runtime.fake import FakeNode
from turtlectl.runtime.roles import goal_services, interface_of


class Navigator:
    Params = msgspec.defstruct("NavigatorParams", [])
    Interface = Interface(publishes=("turtle1/cmd_vel",), goals=("navigate_to",))

    def __init__(self, node):
        self.server = node.goal_server(
            "navigate_to",
            NavigateToRequest,
            NavigateToFeedback,
            NavigateToResponse,
            execute=lambda goal: None,
            on_cancel=lambda goal, reason: NavigateToResponse(success=False, time_taken=0.0, reason=reason),
        )


def test_a_goal_service_stands_for_its_cancel_its_feedback_and_its_callers_tokens():
    resolved = interface_of("turtle2/navigator", Navigator.Interface)
    assert set(resolved.serves) == {"turtle2/navigate_to", "turtle2/navigate_to/cancel"}
    assert set(resolved.publishes) == {"turtle2/cmd_vel", "turtle2/navigate_to/feedback"}
    assert resolved.watches == ("@turtlectl/client/**",)
    assert goal_services(resolved) == ("turtle2/navigate_to",)


def test_a_node_declaring_only_goals_may_serve_its_goal_service():
    with FakeNode(Navigator) as fake:  # no OutsideInterface: the server's declarations are inside it
        goal = fake.send_goal("navigate_to", NavigateToRequest(x=2.0, y=2.0, theta=0.0))
        assert goal.cancel().ok and goal.result.reason == "canceled"


def test_the_built_in_navigators_goal_service_is_one_the_operator_may_call():
    assert launch_goal_services({"navigator": KINDS["navigator"]}, {}) == ["navigate_to"]
