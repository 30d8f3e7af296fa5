"""The navigator process: serves ``navigate_to`` and drives the turtle there.

The goal lifecycle (accepted or refused, feedback, reached, preempted, canceled, caller
gone, no pose, timeout, blocked, teleported, reset) is nodes.goal_machine, and the
driving of a goal (path, control law, obstacles, arriving at rest) nodes.driver, both pure
and tested with a fake clock; this module is their wiring to Zenoh.  Each input (a goal, a
cancel, a pose, a scan, a status, a caller's liveliness token going away, the watchdog
and feedback timers, shutdown) becomes an event of the machine with ``self.node.clock()``,
and what the machine returns is carried out: ``turtle1/cmd_vel`` published, callers
answered, lines logged.  It publishes ``turtle1/cmd_vel`` only while a goal runs, and
refuses to start while another navigator serves ``navigate_to``.

Only a running goal needs every pose (each one is a control step): while one runs, each
``turtle1/pose`` is an event, and while none does no pose wakes this process, nor do the
watchdog and feedback timers (paused: their events do nothing without a goal).  The pose
and ``robot/status`` are kept by Zenoh (``Node.latest``) and handed to the machine when it
needs them: before a goal starts (where from, battery) and before a scan (its origin).
"""

from __future__ import annotations

from turtlectl.messages import (
    Ack,
    Cancel,
    LaserScan,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    Turtles,
    TurtleStatus,
    Twist,
)
from turtlectl.messages.keys import (
    CANCEL,
    CLIENT_TOKEN_PREFIX,
    CMD_VEL,
    FEEDBACK,
    NAVIGATE_TO,
    OBSTACLES,
    POSE,
    STATUS,
    TURTLES,
)
from turtlectl.nodes.goal_machine import Action, GoalMachine, Reply
from turtlectl.nodes.params import NavigatorParams
from turtlectl.runtime import Node, Request, run_main

WATCHDOG_PERIOD = 0.05  # s


class Navigator:
    def __init__(self, node: Node[NavigatorParams]):
        self.node = node
        self.machine: GoalMachine[Request[NavigateToRequest]] = GoalMachine(
            node.params, node.world, node.limits, node.turtle
        )
        self.cmd_pub = node.publisher(CMD_VEL, Twist)
        self.feedback_pub = node.publisher(FEEDBACK, NavigateToFeedback)
        self.pose = node.latest(POSE, Pose, follow=True)  # every pose (self.on_pose) only while a goal runs
        self.status = node.latest(STATUS, TurtleStatus)
        self.turtles = node.latest(f"/{TURTLES}", Turtles)  # the others (nodes.traffic), read at each control step
        self.turtles_seen: Turtles | None = None
        node.subscribe(OBSTACLES, LaserScan, self.on_scan)
        node.serve(NAVIGATE_TO, NavigateToRequest, NavigateToResponse, self.on_goal)
        node.serve(CANCEL, Cancel, Ack, self.on_cancel)
        node.watch_liveliness(f"{CLIENT_TOKEN_PREFIX}/**", self.on_client)
        self.goal_timers = [  # their events do nothing while no goal runs: paused then
            node.timer(WATCHDOG_PERIOD, self.watchdog),
            node.timer(1.0 / node.params.feedback_rate, self.feedback),
        ]
        node.on_params(self.on_params)
        node.on_shutdown(lambda: self.carry_out(self.machine.shutdown(self.node.clock())))
        self.follow_goal()

    # -- inputs -------------------------------------------------------------
    def on_goal(self, request: Request[NavigateToRequest]) -> None:
        self.catch_up()
        self.carry_out(self.machine.start(request.body, request, self.node.clock()))
        goal = self.machine.goal
        path = goal.driver.path if goal is not None else None
        if goal is not None and path is not None:
            how = "straight" if path.direct else f"round obstacles, {len(goal.driver.outline)} points"
            self.node.log.debug("planned %.2f m %s", path.length, how)

    def on_cancel(self, request: Request[Cancel]) -> None:
        ack, actions = self.machine.cancel(request.body.reason, self.node.clock())
        self.carry_out(actions)
        request.respond(ack)

    def on_params(self, params: NavigatorParams) -> None:
        self.machine.set_params(params)
        self.goal_timers[1].retime(1.0 / params.feedback_rate)
        self.follow_goal()  # a retimed timer ticks again: paused once more while no goal runs

    def on_client(self, key: str, alive: bool) -> None:
        if not alive:
            self.carry_out(self.machine.caller_gone(key, self.node.clock()))

    def on_pose(self, pose: Pose) -> None:
        now = self.node.clock()
        self.others(now)
        self.carry_out(self.machine.pose(pose, now))

    def others(self, now: float) -> None:
        """Hand the machine the newest ``turtles`` (the other turtles: nodes.traffic)."""
        turtles = self.turtles.get()
        if turtles is not None and turtles is not self.turtles_seen:
            self.turtles_seen = turtles
            self.machine.turtles(turtles, now)

    def on_scan(self, scan: LaserScan) -> None:
        self.catch_up()
        self.carry_out(self.machine.scan(scan, self.node.clock()))

    def watchdog(self) -> None:
        now = self.node.clock()
        newest, stepped = self.pose.get(), self.machine.latest_pose  # the ring has every pose that came
        if newest is not None and stepped is not None and newest.stamp > stepped.stamp:
            self.machine.pose_heard(now)  # its control step is still queued: behind, not without poses
        self.carry_out(self.machine.tick(now))

    def feedback(self) -> None:
        progress = self.machine.feedback(self.node.clock())
        if progress is not None:
            caller, fb = progress
            stamped = self.feedback_pub.publish(fb)  # for observers
            caller.respond(stamped, final=False)  # the same, stamped, to the caller

    def catch_up(self) -> None:
        """Hand the machine the newest status, and while no goal runs the newest pose (while
        one runs, each pose is already an event).  While idle a pose only updates where the
        turtle is (no control step), which is all the machine does with one then."""
        status = self.status.get()
        if status is not None:
            self.machine.status(status)
        self.others(self.node.clock())  # also while idle: a scan's hits on another turtle are not remembered
        if self.machine.goal is None:
            pose = self.pose.get()
            if pose is not None and pose is not self.machine.latest_pose:
                self.carry_out(self.machine.pose(pose, self.node.clock()))

    # -- outputs ------------------------------------------------------------
    def carry_out(self, actions: list[Action]) -> None:
        """Do what the machine asks, in its order: commands, answers to callers, log lines;
        then follow the goal (it may have started or ended)."""
        for action in actions:
            if isinstance(action, Twist):
                self.cmd_pub.publish(action)
            elif isinstance(action, Reply):
                action.to.respond(action.response)
            else:
                self.node.log.log(action.level, action.text)
        self.follow_goal()

    def follow_goal(self) -> None:
        """While a goal runs: every pose, the watchdog and feedback; while none does, none of them."""
        running = self.machine.goal is not None
        self.pose.each(self.on_pose if running else None)
        for timer in self.goal_timers:
            if running:
                timer.resume()
            else:
                timer.pause()


def main() -> None:
    run_main(Navigator, NavigatorParams)


if __name__ == "__main__":
    main()
