"""Patrol: drives the turtle round a square, goal after goal, through the navigator's
``navigate_to`` service (as a Nav2 waypoint follower would)."""

from __future__ import annotations

from typing import Annotated

import msgspec

from messages import Corner, square  # this project's messages.py
from turtlectl import Node, run_main
from turtlectl.messages import NavigateToRequest, NavigateToResponse


class PatrolParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    side: Annotated[float, msgspec.Meta(gt=0.0, le=8.0)] = 3.0  # m: the square's side
    cx: Annotated[float, msgspec.Meta(ge=0.0, le=100.0)] = 5.5  # m: the square's centre, x
    cy: Annotated[float, msgspec.Meta(ge=0.0, le=100.0)] = 5.5  # m: the square's centre, y
    laps: Annotated[int, msgspec.Meta(ge=0)] = 1  # -: laps to drive (0: for ever)
    goal_timeout: Annotated[float, msgspec.Meta(gt=0.0, le=600.0)] = 60.0  # s: one corner at most


class Patrol:
    """Sends the next corner once a second while no goal runs; a corner not reached (refused,
    timed out, no navigator yet) is tried again."""

    Params = PatrolParams

    def __init__(self, node: Node[PatrolParams]):
        self.node = node
        self.corners: list[Corner] = square(node.params.cx, node.params.cy, node.params.side)
        self.reached = 0  # corners reached so far
        self.busy = False
        self.timer = node.timer(1.0, self.next_goal)

    @property
    def done(self) -> bool:
        laps = self.node.params.laps
        return laps > 0 and self.reached >= 4 * laps

    def next_goal(self) -> None:
        if self.busy or self.done:
            return
        corner = self.corners[self.reached % 4]
        self.busy = True
        goal = NavigateToRequest(x=corner.x, y=corner.y, theta=corner.theta)
        self.node.call("navigate_to", goal, self.answered, timeout=self.node.params.goal_timeout)

    def answered(self, replies: list) -> None:
        self.busy = False
        response = next((r for r in replies if isinstance(r, NavigateToResponse)), None)
        if response is None:
            self.node.log.warning("no answer from navigate_to (is the navigator running?); trying again")
        elif not response.success:
            self.node.log.warning("corner %d not reached (%s); trying again", self.reached % 4, response.reason)
        else:
            self.reached += 1
            self.node.log.info("corner %d reached (%d in all)", (self.reached - 1) % 4, self.reached)
            if self.done:
                self.node.log.info("patrol done: %d laps", self.node.params.laps)
                self.timer.undeclare()


if __name__ == "__main__":
    run_main(Patrol, PatrolParams)
