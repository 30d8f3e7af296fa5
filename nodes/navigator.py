"""The navigator process: serves ``navigate_to`` and drives the turtle there.

``navigate_to`` is a goal service (``Node.goal_server``, runtime.goals), as any user's
navigator's would be: the server does preemption, ``navigate_to/cancel``, the caller going
away, ``goal_timeout``, feedback at ``feedback_rate`` (to the caller and on
``navigate_to/feedback``), shutdown and exactly one answer per goal.  The rest of a goal's
lifecycle (refused, driven, reached, no pose, blocked, and each answer's content) is
nodes.goal_machine, and the driving of a goal (path, control law, obstacles, arriving at
rest) nodes.driver, both pure and tested with a fake clock; this module is their wiring.
Each input (a goal, a pose, a scan, a status, the watchdog timer, the server ending a goal,
the simulator about to move the turtle: ``turtle1/moving``)
becomes an event of the machine with ``self.node.clock()``, and what the machine returns is
carried out: ``turtle1/cmd_vel`` published, goals finished, lines logged.  It publishes
``turtle1/cmd_vel`` only while a goal runs, and refuses to start while another navigator
serves ``navigate_to``.

Only a running goal needs every pose (each one is a control step): while one runs, each
``turtle1/pose`` is an event, and while none does no pose wakes this process, nor does the
watchdog (paused: its events do nothing without a goal).  The pose
and ``robot/status`` are kept by Zenoh (``Node.latest``) and handed to the machine when it
needs them: before a goal starts (where from, battery) and before a scan (its origin).
"""

from __future__ import annotations

from turtlectl.messages import (
    Ack,
    LaserScan,
    Moving,
    NavigateToFeedback,
    NavigateToRequest,
    NavigateToResponse,
    Pose,
    Turtles,
    TurtleStatus,
    Twist,
)
from turtlectl.messages.angles import degrees_0_360
from turtlectl.messages.keys import (
    CMD_VEL,
    MOVING,
    NAVIGATE_TO,
    OBSTACLES,
    POSE,
    STATUS,
    TURTLES,
)
from turtlectl.nodes.goal_machine import Action, GoalMachine, Reply
from turtlectl.nodes.params import NAVIGATOR_CLAIMS, NAVIGATOR_INTERFACE, NavigatorParams
from turtlectl.runtime import Node, Request, run_main
from turtlectl.runtime.goals import GoalHandle

#: a goal of navigate_to, as the goal server hands it over
NavigateGoal = GoalHandle[NavigateToRequest, NavigateToFeedback, NavigateToResponse]

WATCHDOG_PERIOD = 0.05  # s


class Navigator:
    Params = NavigatorParams
    Claims = NAVIGATOR_CLAIMS
    Interface = NAVIGATOR_INTERFACE

    def __init__(self, node: Node[NavigatorParams]):
        self.node = node
        self.machine: GoalMachine[NavigateGoal] = GoalMachine(
            node.params, node.world, node.limits, node.turtle, node.resolve(POSE)
        )
        self.cmd_pub = node.publisher(CMD_VEL, Twist)
        self.pose = node.latest(POSE, Pose, follow=True)  # every pose (self.on_pose) only while a goal runs
        self.status = node.latest(STATUS, TurtleStatus)
        self.turtles = node.latest(f"/{TURTLES}", Turtles)  # the others (nodes.traffic), read at each control step
        self.turtles_seen: Turtles | None = None
        node.subscribe(OBSTACLES, LaserScan, self.on_scan)
        node.serve(MOVING, Moving, Ack, self.on_moving)
        self.server = node.goal_server(
            NAVIGATE_TO,
            NavigateToRequest,
            NavigateToFeedback,
            NavigateToResponse,
            refuse=self.refuse,
            execute=self.on_goal,
            on_cancel=self.on_end,
            feedback=lambda goal: self.machine.feedback(self.node.clock()),
            feedback_rate=node.params.feedback_rate,
            timeout=node.params.goal_timeout,
        )
        self.watchdog_timer = node.timer(WATCHDOG_PERIOD, self.watchdog)  # does nothing while no goal runs: paused
        node.on_params(self.on_params)
        self.follow_goal()

    # -- inputs -------------------------------------------------------------
    def refuse(self, request: NavigateToRequest) -> NavigateToResponse | None:
        self.feed_latest_inputs()
        refused = self.machine.refusal(request)
        if refused is None:
            return None
        response, note = refused
        self.node.log.log(note.level, note.text)
        return response

    def on_goal(self, goal: NavigateGoal) -> None:
        target = goal.request
        goal.summary = f"({target.x:g}, {target.y:g}, {degrees_0_360(target.theta):g} deg)"
        self.carry_out(self.machine.start(target, goal, self.node.clock()))
        running = self.machine.goal
        path = running.driver.path if running is not None else None
        if running is not None and path is not None:
            how = "straight" if path.direct else f"round obstacles, {len(running.driver.outline)} points"
            self.node.log.debug("planned %.2f m %s", path.length, how)

    def on_end(self, goal: NavigateGoal, reason: str) -> None:
        """The goal server ends the goal (preempted, canceled, caller gone, timeout, shut
        down): the machine stops the turtle and finishes it with its answer."""
        self.carry_out(self.machine.end(reason, self.node.clock(), goal.end_detail))

    def on_moving(self, request: Request[Moving]) -> None:
        """The simulator is about to put the turtle elsewhere (a teleport, a reset): the running
        goal ends with its reason ("teleported", "reset") before the turtle moves, so no command
        is computed from a pose that no longer holds."""
        ended = self.server.cancel(request.body.reason)
        request.respond(Ack(detail="ended the running goal" if ended else "no goal is running"))

    def on_params(self, params: NavigatorParams) -> None:
        self.machine.set_params(params)
        self.server.feedback_rate = params.feedback_rate
        self.server.timeout = params.goal_timeout

    def on_pose(self, pose: Pose) -> None:
        now = self.node.clock()
        self.feed_other_turtles(now)
        self.carry_out(self.machine.pose(pose, now))

    def feed_other_turtles(self, now: float) -> None:
        """Hand the machine the newest ``turtles`` (the other turtles: nodes.traffic)."""
        turtles = self.turtles.get()
        if turtles is not None and turtles is not self.turtles_seen:
            self.turtles_seen = turtles
            self.machine.turtles(turtles, now)

    def on_scan(self, scan: LaserScan) -> None:
        self.feed_latest_inputs()
        self.carry_out(self.machine.scan(scan, self.node.clock()))

    def watchdog(self) -> None:
        now = self.node.clock()
        newest, stepped = self.pose.get(), self.machine.latest_pose  # the ring has every pose that came
        if newest is not None and stepped is not None and newest.stamp > stepped.stamp:
            self.machine.pose_heard(now)  # its control step is still queued: behind, not without poses
        self.carry_out(self.machine.tick(now))

    def feed_latest_inputs(self) -> None:
        """Hand the machine the newest status, and while no goal runs the newest pose (while
        one runs, each pose is already an event).  While idle a pose only updates where the
        turtle is (no control step), which is all the machine does with one then."""
        status = self.status.get()
        if status is not None:
            self.machine.status(status)
        # also while idle: a scan's hits on another turtle are not remembered
        self.feed_other_turtles(self.node.clock())
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
                action.to.finish(action.response)
            else:
                self.node.log.log(action.level, action.text)
        self.follow_goal()

    def follow_goal(self) -> None:
        """While a goal runs: every pose and the watchdog; while none does, neither."""
        running = self.machine.goal is not None
        self.pose.each(self.on_pose if running else None)
        if running:
            self.watchdog_timer.resume()
        else:
            self.watchdog_timer.pause()


def main() -> None:
    run_main(Navigator, NavigatorParams)


if __name__ == "__main__":
    main()
