"""SpeedLimit: a safety filter between a navigator and its turtle, as a ROS velocity smoother or
collision monitor sits between Nav2's controller and the base.  The navigator's commands come
in on ``safety/cmd_vel`` (its ``turtle1/cmd_vel`` remapped there in turtle.toml) and go out on
``turtle1/cmd_vel``, slower than ``max_speed``: both speeds scaled down by one factor, so the
turtle keeps to the navigator's path, only slower.  In a namespace (``turtle2``) its keys are
that turtle's: ``turtle2/safety/cmd_vel`` in, ``turtle2/cmd_vel`` out."""

from __future__ import annotations

from typing import Annotated

import msgspec

from turtlectl import Interface, Node, run_main
from turtlectl.messages import Twist


class SpeedLimitParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    max_speed: Annotated[float, msgspec.Meta(gt=0.0, le=4.0)] = 1.0  # m/s: the fastest the turtle is let go


class SpeedLimit:
    Params = SpeedLimitParams
    # what it does, resolved in its namespace: under `launch --secure` the router allows exactly this
    Interface = Interface(publishes=("turtle1/cmd_vel",), subscribes=("safety/cmd_vel",))

    def __init__(self, node: Node[SpeedLimitParams]):
        self.node = node
        self.out = node.publisher("turtle1/cmd_vel", Twist)
        node.subscribe("safety/cmd_vel", Twist, self.on_command)

    def on_command(self, cmd: Twist) -> None:
        limit = self.node.params.max_speed  # read where used: `param set` takes effect at once
        scale = min(1.0, limit / abs(cmd.linear)) if cmd.linear else 1.0
        self.out.publish(Twist(linear=cmd.linear * scale, angular=cmd.angular * scale))


if __name__ == "__main__":  # importing the file must not run it: launch imports it to check its Params
    run_main(SpeedLimit, SpeedLimitParams)
