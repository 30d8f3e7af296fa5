"""The navigator's goal lifecycle, every transition, as scripted histories of events on a
fake clock (plain floats): no processes, no Zenoh, no sleeping."""

from __future__ import annotations

import logging
import math

import msgspec
import numpy as np
import pytest

from turtlectl.cli.tools.teleop import TAKEN_OVER
from turtlectl.messages import GoalState, LaserScan, NavigateToRequest, Pose, TurtleStatus, Twist
from turtlectl.messages.world import Limits, Obstacle, World
from turtlectl.nodes.goal_machine import GoalMachine, Note, Reply
from turtlectl.nodes.params import NavigatorParams
from turtlectl.sim.kinematics import STEP, TurtleState, accelerate, effective_command, step

PARAMS = NavigatorParams(blocked_timeout=3.0, goal_timeout=30.0, pose_timeout=0.5, scan_timeout=1.0)
WORLD = World(size=11.0)
LIMITS = Limits()


def machine(world: World = WORLD, **params) -> GoalMachine[str]:
    return GoalMachine(msgspec.structs.replace(PARAMS, **params), world, LIMITS)


def goal(x=8.0, y=5.0, theta=0.0, client="") -> NavigateToRequest:
    return NavigateToRequest(x=x, y=y, theta=theta, client=client)


def pose(x=2.0, y=5.0, theta=0.0) -> Pose:
    return Pose(x=x, y=y, theta=theta)


def scan(blocking: bool, at: Pose | None = None) -> LaserScan:
    """A full-circle scan; with ``blocking``, something 0.3 m in every direction.  Taken
    at ``at`` (None: the scan does not say where)."""
    n = 72
    where = {} if at is None else {"origin_x": at.x, "origin_y": at.y, "origin_theta": at.theta}
    return LaserScan(
        angle_min=-math.pi,
        angle_max=math.pi - 2 * math.pi / n,
        angle_increment=2 * math.pi / n,
        range_min=0.0,
        range_max=10.0,
        ranges=[0.3 if blocking else math.inf] * n,
        **where,
    )


def replies(actions) -> list[Reply]:
    return [a for a in actions if isinstance(a, Reply)]


def twists(actions) -> list[Twist]:
    return [a for a in actions if isinstance(a, Twist)]


def notes(actions) -> list[str]:
    return [a.text for a in actions if isinstance(a, Note)]


def only_reply(actions) -> Reply:
    (reply,) = replies(actions)
    return reply


def submit(m: GoalMachine[str], request: NavigateToRequest, caller: str = "caller", now: float = 0.0) -> list:
    """A goal as the goal server (runtime.goals, tested in tests/unit/runtime/test_goals.py)
    hands it to the navigator: the machine's refusal is its only answer, else the running goal
    ends "preempted" and the new one starts."""
    refused = m.refusal(request)
    if refused is not None:
        response, note = refused
        return [note, Reply(caller, response)]
    return m.end("preempted", now) + m.start(request, caller, now)


def running(m: GoalMachine[str], now: float = 0.0, request=None, caller="caller") -> list:
    """Start a goal from (2, 5) facing it, with a pose known."""
    m.pose(pose(), now)
    actions = submit(m, request or goal(), caller, now)
    assert m.goal is not None, actions
    return actions


# -- accepted or refused ------------------------------------------------------
def test_a_goal_is_accepted_and_driven_at_once_from_the_latest_pose():
    m = machine()
    m.pose(pose(), 0.0)
    actions = submit(m, goal(), "caller", 0.0)
    assert m.goal is not None and m.goal.caller == "caller" and m.goal.start == 0.0
    assert notes(actions) == [
        "goal (8.000, 5.000, 0.0 deg)",
        "no recent scan: avoiding only the declared obstacles of the world",
    ]
    (cmd,) = twists(actions)
    assert cmd.linear > 0.0 and replies(actions) == []


def test_a_goal_without_a_pose_waits_for_one():
    m = machine()
    actions = submit(m, goal(), "caller", 0.0)
    assert m.goal is not None and twists(actions) == []
    assert m.feedback(0.1) is None  # nothing to say without a pose
    assert twists(m.pose(pose(), 0.1))[0].linear > 0.0


def test_with_a_recent_scan_no_warning_at_the_start():
    m = machine()
    m.pose(pose(), 0.0)
    m.scan(scan(False, pose()), 0.0)
    assert notes(submit(m, goal(), "caller", 0.5)) == ["goal (8.000, 5.000, 0.0 deg)"]


@pytest.mark.parametrize(
    "request_, starts",
    [
        (goal(x=math.nan), "x is nan"),
        (goal(theta=math.inf), "theta is inf"),
        (goal(x=20.0), "(20, 5) is outside the world"),
    ],
)
def test_an_invalid_goal_is_refused_at_once(request_, starts):
    m = machine()
    actions = submit(m, request_, "caller", 3.0)
    reply = only_reply(actions)
    assert reply.to == "caller" and reply.response.refused and not reply.response.success
    assert reply.response.time_taken == 0.0
    # a short reason for programs, the sentence in detail (not all of it in the reason)
    assert reply.response.reason == "invalid goal" and reply.response.detail.startswith(starts), reply
    assert (reply.response.x, reply.response.y) == (0.0, 0.0)  # no pose known: no position
    assert notes(actions)[0].startswith("refused goal (") and m.goal is None and twists(actions) == []


def test_a_goal_walled_in_by_declared_obstacles_is_refused_with_the_pose():
    ring = [Obstacle(x=8.0 + 1.2 * math.cos(a), y=5.0 + 1.2 * math.sin(a), radius=0.3) for a in range(0, 7)]
    m = machine(World(size=11.0, obstacles=ring))
    m.pose(pose(theta=math.pi / 2), 0.0)
    reply = only_reply(submit(m, goal(), "caller", 0.0))
    assert reply.response.refused and reply.response.reason == "unreachable"
    assert reply.response.detail.startswith("no way from (2.00, 5.00)")
    assert reply.response.detail.endswith("the goal is walled in by obstacles")
    assert (reply.response.x, reply.response.y, reply.response.theta) == pytest.approx((2.0, 5.0, 90.0))


def test_a_turtle_walled_in_is_told_so_not_that_the_goal_is():
    """From inside a ring, a goal in open space is not refused with "the goal is walled in by
    obstacles"."""
    ring = [Obstacle(x=2.0 + 1.2 * math.cos(a), y=5.0 + 1.2 * math.sin(a), radius=0.3) for a in range(0, 7)]
    m = machine(World(size=11.0, obstacles=ring))
    m.pose(pose(), 0.0)  # (2, 5): the ring's centre
    reason = only_reply(submit(m, goal(), "caller", 0.0)).response.detail
    assert reason.endswith("the turtle is walled in by obstacles"), reason
    assert "the goal is" not in reason


@pytest.mark.parametrize(
    ("turtle", "target", "walled"), [((0.2, 0.2), (5.0, 5.0), "turtle"), ((5.0, 5.0), (0.2, 0.2), "goal")]
)
def test_a_pocket_between_an_obstacle_and_a_corner_is_told_as_walling_in_what_is_in_it(turtle, target, walled):
    """A turtle in a corner closed off by an obstacle is not told "the goal is walled in": the
    pocket holds a corner of the world, which must not count as reaching out."""
    m = machine(World(size=11.0, obstacles=[Obstacle(x=1.0, y=1.0, radius=0.6)]))
    m.pose(pose(*turtle), 0.0)
    reason = only_reply(submit(m, goal(*target), "caller", 0.0)).response.detail
    assert reason.endswith(f"the {walled} is walled in by obstacles"), reason


def test_a_goal_behind_a_declared_obstacle_gets_a_path_round_it():
    m = machine(World(size=11.0, obstacles=[Obstacle(x=5.0, y=5.0, radius=0.5)]))
    running(m)
    fb = m.feedback(0.0)
    assert len(fb.path) > 3 and fb.path[0] == pytest.approx((2.0, 5.0)) and fb.path[-1] == pytest.approx((8.0, 5.0))
    assert max(abs(y - 5.0) for _, y in fb.path) >= 0.95 - 1e-9  # round it, 0.45 m clear of it
    assert fb.distance_remaining > 6.0 and fb.replans == 0


def test_battery_low_refuses_and_a_refusal_leaves_the_running_goal_alone():
    m = machine()
    running(m)
    m.status(TurtleStatus(x=2, y=5, theta=0, vel_x=0, vel_y=0, battery=3.0))
    actions = submit(m, goal(x=3.0), "second", 1.0)
    reply = only_reply(actions)
    assert reply.to == "second" and reply.response.reason == "battery low"
    assert reply.response.detail == (
        "battery at 3.0 %, below the navigator's min_battery 5 %: `turtlectl reset` recharges it"
    )
    assert notes(actions) == [f"refused goal (3, 5, 0.0 deg): battery low: {reply.response.detail}"]
    assert m.goal is not None and m.goal.caller == "caller"


def test_the_goal_heading_is_reduced_in_degrees():
    m = machine()
    running(m, request=goal(theta=1e16))
    assert m.goal.theta_deg == pytest.approx(280.0)
    fb = m.feedback(0.0)
    assert fb.goal_theta == pytest.approx(280.0)


# -- reached ------------------------------------------------------------------
def test_a_goal_reached_stops_the_turtle_then_answers():
    m = machine()
    running(m, now=10.0)
    assert m.pose(pose(x=8.0), 11.2) == [Twist()]  # there: stopped (the last command drove it)
    actions = m.pose(pose(x=8.0), 11.25)  # and still there, with nothing but the stop on its way
    assert actions[0] == Twist()  # the stop comes before the answer
    reply = only_reply(actions)
    assert reply.to == "caller" and reply.response.success and reply.response.reason == ""
    assert reply.response.time_taken == 1.25 and reply.response.position_error == 0.0
    assert notes(actions) == ["goal reached in 1.250 s (error 0.0000 m, 0.00 deg)"]
    assert m.goal is None and m.pose(pose(x=8.0), 11.3) == []  # idle: no more commands


def test_a_turtle_still_turning_within_the_tolerances_is_not_reached_until_it_rests():
    """A turtle turning at speed through the goal heading has not succeeded: braking would
    carry it 2 deg past.  Reached means at rest within the tolerances,
    and the response gives the pose it rests in."""
    m = machine()
    running(m, now=10.0)
    actions = m.pose(Pose(x=8.0, y=5.0, theta=0.001, angular_velocity=2.0), 11.0)
    assert replies(actions) == [] and twists(actions) == [Twist()]  # stop turning, and wait
    assert m.goal is not None
    rest = Pose(x=8.0, y=5.0, theta=0.003)  # where braking left it: still within 0.25 deg
    reply = only_reply(m.pose(rest, 11.05))
    assert reply.response.success and reply.response.time_taken == pytest.approx(1.05)
    assert reply.response.theta == pytest.approx(math.degrees(0.003))
    assert reply.response.heading_error == pytest.approx(math.degrees(0.003))


def test_a_turtle_that_comes_to_rest_outside_the_tolerance_turns_back():
    m = machine()
    running(m, now=0.0)
    m.pose(Pose(x=8.0, y=5.0, theta=-0.002, angular_velocity=2.0), 1.0)
    actions = m.pose(Pose(x=8.0, y=5.0, theta=0.03), 1.05)  # braked 1.7 deg past the heading
    assert replies(actions) == [] and m.goal is not None
    assert twists(actions)[-1].angular < 0.0  # back towards it


def test_a_turtle_at_rest_between_the_aim_and_the_tolerance_has_arrived():
    """The law aims at half the tolerances; a turtle that comes to rest 0.4 deg off (of 0.5)
    is within what the caller asked: reached, not turned again."""
    m = machine()
    running(m, now=0.0)
    m.pose(Pose(x=8.0, y=5.0, theta=-0.001, angular_velocity=2.0), 1.0)
    reply = only_reply(m.pose(Pose(x=8.0, y=5.0, theta=math.radians(0.4)), 1.05))
    assert reply.response.success and reply.response.heading_error == pytest.approx(0.4)


def test_a_turtle_drifting_at_the_goal_position_is_not_reached_until_it_rests():
    m = machine()
    running(m, now=0.0)
    actions = m.pose(Pose(x=8.0, y=5.0, theta=0.0, linear_velocity=0.3), 1.0)
    assert replies(actions) == [] and m.goal is not None


def test_a_turtle_that_would_rest_inside_the_tolerances_is_stopped_without_creeping_on():
    """2 deg short of the heading, turning towards it at 2 rad/s: stopped now, it brakes
    1.98 deg in three steps and rests inside the 0.25 deg the law aims at, so it is stopped
    (the law would turn on at 1.4 rad/s)."""
    m = machine()
    running(m, now=0.0)
    actions = m.pose(Pose(x=8.0, y=5.0, theta=-math.radians(2.0), angular_velocity=2.0), 1.0)
    assert replies(actions) == [] and twists(actions) == [Twist()]
    rest = -math.radians(2.0) + (1.36 + 0.72 + 0.08) * STEP  # 2 rad/s less 0.64 rad/s a step
    reply = only_reply(m.pose(Pose(x=8.0, y=5.0, theta=rest), 1.05))
    assert reply.response.success and reply.response.heading_error == pytest.approx(0.02, abs=0.005)


def test_closed_loop_with_a_late_command_rests_within_the_tolerances_where_it_said():
    """The machine against the simulator's kinematics, each command taking effect a step late
    (as in the system: the simulator applies the command that came after the pose it
    published), arriving fast and turning: the response's pose is where it rests."""
    m = machine()
    now, outcome, pending = 0.0, None, [Twist()]
    s = TurtleState(x=7.99, y=5.0, theta=math.radians(40.0), w=-LIMITS.max_angular_speed)
    submit(m, goal(x=8.0, theta=0.0), "caller", now)
    for _ in range(2000):
        pose = Pose(x=s.x, y=s.y, theta=s.theta, linear_velocity=s.v, angular_velocity=s.w)
        actions = m.pose(pose, now) if m.goal is not None else []
        outcome = outcome or next(iter(replies(actions)), None)
        pending.append(twists(actions)[-1] if twists(actions) else pending[-1])
        cmd = pending.pop(0)
        v, w = effective_command(cmd.linear, cmd.angular, 0.0, LIMITS)
        s = step(s, *accelerate(s, v, w, STEP, LIMITS), STEP, WORLD.size)
        now += STEP
        if outcome is not None and s.v == 0.0 and s.w == 0.0 and pending == [Twist()]:
            break
    assert outcome is not None and outcome.response.success, outcome
    rest_heading = abs(math.degrees(s.theta))
    assert rest_heading <= PARAMS.heading_tolerance
    assert math.hypot(s.x - 8.0, s.y - 5.0) <= PARAMS.position_tolerance
    assert outcome.response.theta == pytest.approx(math.degrees(s.theta) % 360.0, abs=1e-9)


def test_a_goal_where_the_turtle_stands_is_reached_on_start():
    m = machine()
    m.pose(pose(x=8.0), 0.0)
    actions = submit(m, goal(), "caller", 0.0)
    assert only_reply(actions).response.success and m.goal is None


def test_closed_loop_on_the_kinematics_reaches_the_goal_turning_then_driving():
    """The machine against the simulator's kinematics, a pose every 16 ms of fake time."""
    m = machine()
    s, now = TurtleState(x=2.0, y=5.0, theta=math.pi), 0.0
    submit(m, goal(theta=90.0), "caller", now)
    states, outcome = [], None
    while outcome is None and now < 5.0:
        actions = m.pose(Pose(x=s.x, y=s.y, theta=s.theta), now)
        if m.goal is not None:
            states.append(m.feedback(now).state)
        outcome = next(iter(replies(actions)), None)
        cmd = twists(actions)[-1]
        v, w = effective_command(cmd.linear, cmd.angular, 0.0, LIMITS)
        s = step(s, *accelerate(s, v, w, STEP, LIMITS), STEP, WORLD.size)
        now += STEP
    assert outcome is not None and outcome.response.success, outcome
    assert outcome.response.position_error <= PARAMS.position_tolerance
    assert outcome.response.heading_error <= PARAMS.heading_tolerance
    assert GoalState.DRIVING in states and GoalState.TURNING in states


# -- preempted, canceled, caller gone, teleported, reset, shut down -----------
def test_a_new_goal_preempts_the_running_one():
    m = machine()
    running(m, caller="first")
    actions = submit(m, goal(x=3.0, y=3.0, theta=-180.0), "second", 2.0)
    old = only_reply(actions)
    assert old.to == "first" and old.response.reason == "preempted" and old.response.time_taken == 2.0
    assert old.response.detail == "a new goal replaced it"
    assert m.goal.caller == "second"
    # the old goal ends (stop, log, answer), then the new one starts and drives at once
    assert [type(a).__name__ for a in actions] == ["Twist", "Note", "Reply", "Note", "Note", "Twist"]
    assert actions[0] == Twist() and actions[-1] != Twist()
    assert notes(actions)[1:] == [
        "goal (3.000, 3.000, 180.0 deg)",
        "no recent scan: avoiding only the declared obstacles of the world",
    ]


def test_a_goal_ended_canceled_stops_then_answers():
    m = machine()
    running(m)
    actions = m.end("canceled", 1.5)
    assert actions[0] == Twist()
    reply = only_reply(actions)
    assert reply.response.reason == "canceled" and reply.response.detail == "" and reply.response.time_taken == 1.5
    assert notes(actions) == ["goal failed in 1.500 s (error 6.0000 m, 0.00 deg): canceled"]
    assert m.goal is None


def test_ending_without_a_goal_does_nothing():
    assert machine().end("canceled", 0.0) == []


@pytest.mark.parametrize("how", ["teleported", "reset"])
def test_teleport_and_reset_cancel_with_their_reason(how):
    m = machine()
    running(m)
    reply = only_reply(m.end(how, 1.0))
    assert reply.response.reason == how and reply.response.detail == f"the turtle was {how} while it drove"


def test_a_caller_that_goes_away_is_told_in_the_answer():
    m = machine()
    running(m, request=goal(client="abc"))
    actions = m.end("caller gone", 1.0)
    reply = only_reply(actions)
    assert reply.response.reason == "caller gone"
    assert reply.response.detail == "its caller went away: Ctrl-C, killed, or its own --timeout"
    assert actions[0] == Twist() and m.goal is None


def test_shutdown_ends_the_goal_and_stops_the_turtle():
    m = machine()
    running(m)
    actions = m.end("shut down", 0.2)
    assert actions[0] == Twist()
    assert only_reply(actions).response.reason == "navigator shut down"
    assert machine().end("shut down", 0.0) == []


# -- no pose, timeout ---------------------------------------------------------
def test_no_pose_for_pose_timeout_ends_the_goal():
    m = machine()
    submit(m, goal(), "caller", 10.0)
    assert m.tick(10.5) == []  # pose_timeout 0.5 s, counted from the start
    actions = m.tick(10.51)
    reply = only_reply(actions)
    assert reply.response.reason == "no pose"
    assert reply.response.detail == "no turtle1/pose for 0.5 s: is the simulator running?"
    assert actions[0] == Twist() and m.goal is None


def test_poses_that_stop_arriving_end_the_goal():
    m = machine()
    running(m)
    for t in (0.4, 0.8, 1.2):
        m.pose(pose(), t)
        assert m.tick(t + 0.1) == []
    assert m.tick(1.7) == [] and m.goal is not None  # 0.5 s after the last pose
    assert only_reply(m.tick(1.71)).response.reason == "no pose"


def test_a_pose_heard_but_not_yet_stepped_keeps_the_goal_alive():
    """bench/fleet.py at N=10: a navigator stalled on saturated cores runs its watchdog before the
    poses queued meanwhile; so that it does not fail a goal "no pose", the shell tells the
    machine a newer pose came (Navigator.watchdog, from Node.latest's ring)."""
    m = machine()
    running(m)
    m.pose(pose(), 0.4)
    m.pose_heard(0.85)  # a pose came at 0.85, its control step still queued behind the watchdog
    assert m.tick(1.3) == [] and m.goal is not None
    assert only_reply(m.tick(1.36)).response.reason == "no pose"  # 0.5 s after it, nothing more: silent


def test_goal_timeout_is_the_servers_deadline_and_the_answer_says_it():
    m = machine(goal_timeout=2.0)
    running(m)
    t = 0.0
    while t < 3.0:  # poses keep coming, the turtle never gets there: the watchdog does not end it
        t = round(t + 0.05, 2)
        m.pose(pose(), t)
        assert m.tick(t) == []
    reply = only_reply(m.end("timeout", 2.01))
    assert reply.response.reason == "timeout" and reply.response.time_taken == 2.01
    assert reply.response.detail == "not there after the navigator's goal_timeout of 2 s"


def test_the_watchdog_is_quiet_while_idle():
    assert machine().tick(1e6) == []


# -- blocked, replanning ---------------------------------------------------
def one_hit(distance: float, at: Pose | None = None) -> LaserScan:
    """A scan with a single beam, straight ahead of the turtle at (2, 5), hitting something."""
    where = at or pose()
    return LaserScan(
        angle_min=0.0,
        angle_max=0.0,
        angle_increment=0.1,
        range_min=0.0,
        range_max=10.0,
        ranges=[distance],
        origin_x=where.x,
        origin_y=where.y,
        origin_theta=where.theta,
    )


def walled_in():
    """A goal running from (2, 5), then a scan: something 0.3 m away all round the turtle."""
    m = machine()
    running(m)
    actions = m.scan(scan(True, pose()), 0.0)
    actions += m.pose(pose(), 0.0)
    assert m.goal.state is GoalState.REPLANNING
    return m, actions


def test_something_seen_on_the_way_is_planned_round():
    m = machine()
    running(m)
    assert m.feedback(0.0).path == [pytest.approx((2.0, 5.0)), pytest.approx((8.0, 5.0))]
    actions = m.scan(one_hit(2.0), 0.0)  # something at (4, 5), on the straight way
    (note,) = notes(actions)
    assert note.startswith("planned again (something the scan sees at (4.0") and note.endswith("m to go")
    fb = m.feedback(0.1)
    assert fb.replans == 1 and max(abs(y - 5.0) for _, y in fb.path) > 0.45
    cmd = twists(m.pose(pose(), 0.1))[0]
    assert cmd.linear > 0.0 and m.goal.state is GoalState.DRIVING  # off it goes, round it
    assert notes(m.scan(one_hit(2.0), 0.2)) == []  # the same thing, already planned round: no news


def test_a_scan_that_sees_nothing_in_the_way_changes_nothing():
    m = machine()
    running(m)
    assert m.scan(scan(False, pose()), 0.0) == [] and m.feedback(0.0).replans == 0


def test_walled_in_by_what_the_scan_sees_it_stops_and_replans_with_each_scan():
    m, actions = walled_in()
    assert notes(actions) == ["no way round what the scan sees: waiting, planning again with each scan"]
    assert {(a.linear, a.angular) for a in twists(actions)} == {(0.0, 0.0)} and replies(actions) == []
    fb = m.feedback(0.1)
    assert fb.state is GoalState.REPLANNING and fb.path == []


def test_no_way_for_blocked_timeout_ends_the_goal_blocked():
    m, _ = walled_in()
    actions = sensor(m, 0.05, 3.0, blocking=True)
    assert replies(actions) == [] and m.goal.state is GoalState.REPLANNING
    assert notes(actions) == []  # said once, when it stopped
    assert {(a.linear == 0.0) for a in twists(actions)} == {True}
    actions = m.pose(pose(), 3.01)
    reply = only_reply(actions)
    assert reply.response.reason == "blocked" and reply.response.time_taken == 3.01
    assert reply.response.detail == (
        "there was no way round what the scan sees for the navigator's blocked_timeout of 3 s"
    )
    assert twists(actions)[-1] == Twist() and isinstance(actions[-1], Reply) and m.goal is None


def sensor(m: GoalMachine[str], start: float, end: float, blocking: bool) -> list:
    """From ``start`` to ``end`` s, the sensor at 5 Hz (``blocking`` or not) and a pose every
    50 ms (the turtle stays put); every action in order."""
    actions, t = [], start
    while t <= end + 1e-9:
        if round(t * 5, 6).is_integer():
            actions += m.scan(scan(blocking, pose()), t)
        actions += m.pose(pose(), t)
        t = round(t + 0.05, 2)
    return actions


def test_a_goal_that_something_seen_sits_on_ends_blocked_saying_so():
    """More than "there was no way round what the scan sees"."""
    m = machine()
    running(m, request=goal(x=3.0))
    m.scan(one_hit(1.1), 0.0)  # something 0.1 m beyond the goal, 1 m ahead
    actions = []
    for k in range(70):
        if k % 4 == 0:
            actions += m.scan(one_hit(1.1), k * 0.05)
        actions += m.pose(pose(), k * 0.05)
    reply = only_reply(actions)
    assert reply.response.reason == "blocked"
    assert reply.response.detail.startswith("something the scan sees lay within 0.45 m of the goal (seen at (3.1"), (
        reply
    )


def test_a_way_that_opens_is_taken_and_the_blocked_time_starts_again():
    m, _ = walled_in()
    assert replies(sensor(m, 0.05, 2.4, blocking=True)) == [] and m.goal.state is GoalState.REPLANNING
    actions = m.scan(scan(False, pose()), 2.5)  # long before the last blocking scan would go stale
    actions += m.pose(pose(), 2.5)
    assert notes(actions) == ["planned again (a way is open): 6.00 m to go", "way clear: resuming"]
    assert twists(actions)[0].linear > 0.0 and m.goal.state is GoalState.DRIVING
    actions = sensor(m, 2.6, 5.6, blocking=True)  # walled in again: 3 s from 2.6, not from 0
    assert notes(actions) == ["no way round what the scan sees: waiting, planning again with each scan"]
    assert replies(actions) == []
    assert only_reply(sensor(m, 5.65, 5.65, blocking=True)).response.reason == "blocked"


def test_something_close_ahead_stops_driving_but_not_turning_and_a_new_way_is_taken():
    m = machine()
    running(m)
    # seen 0.35 m ahead on the straight way, not yet planned round (as if a scan had not come through scan())
    m.surroundings.unknown_points, m.surroundings.scan_time = np.array([[2.35, 5.0]]), 0.0
    actions = m.pose(pose(), 0.0)
    assert notes(actions)[0] == "something the scan sees within 0.40 m in the direction of travel: stopped"
    (cmd,) = twists(actions)
    assert cmd.linear == 0.0 and replies(actions) == [] and m.goal.state is GoalState.BLOCKED


def _drive(m: GoalMachine[str], start: TurtleState, world: World, until: float = 10.0):
    """The machine against the simulator's kinematics, a pose every 16 ms of fake time; the
    outcome and the turtle's states."""
    s, now, states, outcome = start, 0.0, [], None
    while outcome is None and now < until:
        actions = m.pose(Pose(x=s.x, y=s.y, theta=s.theta), now)
        outcome = next(iter(replies(actions)), None)
        cmd = twists(actions)[-1]
        v, w = effective_command(cmd.linear, cmd.angular, 0.0, LIMITS)
        s = step(s, *accelerate(s, v, w, STEP, LIMITS), STEP, world.size)
        states.append(s)
        now += STEP
    return outcome, states


def test_a_turtle_within_an_obstacles_margin_finds_its_way_out_and_round():
    world = World(size=11.0, obstacles=[Obstacle(x=2.4, y=5.0, radius=0.1)])
    m = machine(world)
    submit(m, goal(), "caller", 0.0)  # no pose yet: nothing to judge the way from
    outcome, states = _drive(m, TurtleState(x=2.0, y=5.0, theta=0.0), world)
    assert outcome is not None and outcome.response.success, outcome
    assert min(math.hypot(s.x - 2.4, s.y - 5.0) for s in states) > 0.4 - 0.03  # never nearer than it started


def test_round_a_declared_obstacle_in_one_go_and_exactly_there():
    world = World(size=11.0, obstacles=[Obstacle(x=5.0, y=5.0, radius=0.5)])
    m = machine(world)
    submit(m, goal(theta=90.0), "caller", 0.0)
    outcome, states = _drive(m, TurtleState(x=2.0, y=5.0, theta=0.0), world)
    assert outcome is not None and outcome.response.success, outcome
    assert outcome.response.position_error <= PARAMS.position_tolerance
    assert outcome.response.heading_error <= PARAMS.heading_tolerance
    gaps = [math.hypot(s.x - 5.0, s.y - 5.0) - 0.5 for s in states]
    assert min(gaps) >= PARAMS.robot_radius  # never nearer than the turtle's size
    speeds = [math.hypot(b.x - a.x, b.y - a.y) / STEP for a, b in zip(states, states[1:], strict=False)]
    moving = speeds[speeds.index(max(speeds)) // 4 : int(len(speeds) * 0.6)]
    assert min(moving) > 1.0  # no stop on the way round


def test_an_obstacle_beyond_the_goal_does_not_block():
    m = machine()
    running(m, request=goal(x=3.0))
    assert m.scan(one_hit(1.6), 0.0) == []  # 1.6 m ahead, the goal 1 m ahead and 0.55 m clear of it
    assert twists(m.pose(pose(), 0.0))[0].linear > 0.0 and m.goal.state is GoalState.DRIVING


# -- scans --------------------------------------------------------------------
def test_a_stale_scan_is_forgotten_and_the_feedback_says_so():
    m, _ = walled_in()
    # the first scan does not say "scans are back": nothing had said they stopped
    assert notes(m.tick(0.05)) == []
    assert m.tick(0.1) == []
    assert m.feedback(1.0).scan_stale is False
    actions = m.pose(pose(), 1.01)  # only the declared obstacles now: none
    assert notes(actions) == ["planned again (a way is open): 6.00 m to go", "way clear: resuming"]
    assert m.goal.state is GoalState.DRIVING
    assert m.feedback(1.01).scan_stale is True
    assert notes(m.tick(1.05)) == ["scans stopped: avoiding only the declared obstacles of the world"]
    assert notes(m.tick(1.10)) == []  # said once
    m.scan(scan(False, pose()), 1.2)
    assert notes(m.tick(1.25)) == ["scans are back"]


def test_scan_staleness_is_said_only_while_a_goal_runs():
    m = machine()
    m.scan(scan(False, pose()), 0.0)
    assert m.tick(0.1) == [] and m.tick(5.0) == []


def test_a_scan_without_its_origin_is_placed_at_the_latest_pose():
    m = machine()
    m.scan(scan(True), 0.0)  # no pose yet: ignored
    assert m.scan_points.shape == (0, 2) and not m.scans_fresh(0.0)
    m.pose(pose(), 0.0)
    m.scan(scan(True), 0.1)
    assert m.scans_fresh(0.1) and len(m.scan_points) == 72
    assert min(math.hypot(x - 2.0, y - 5.0) for x, y in m.scan_points) == pytest.approx(0.3)


def test_hits_on_the_walls_are_not_obstacles():
    m = machine()
    at = pose(x=0.3, y=5.0, theta=math.pi)
    beam = LaserScan(angle_min=0.0, angle_max=0.0, angle_increment=0.1, range_min=0.0, range_max=10.0, ranges=[0.3])
    m.scan(msgspec.structs.replace(beam, origin_x=at.x, origin_y=at.y, origin_theta=at.theta), 0.0)
    assert m.scan_points.shape == (0, 2)


# -- feedback -----------------------------------------------------------------
def test_feedback_tells_the_caller_how_it_goes():
    m = machine()
    running(m, now=1.0, request=goal(theta=-90.0), caller="me")
    m.pose(pose(x=4.0, theta=math.pi / 2), 1.4)
    fb = m.feedback(1.5)
    assert fb.distance_remaining == pytest.approx(4.0) and fb.elapsed == pytest.approx(0.5)
    assert (fb.x, fb.y, fb.theta) == pytest.approx((4.0, 5.0, 90.0))
    assert (fb.goal_x, fb.goal_y, fb.goal_theta) == (8.0, 5.0, 270.0)
    assert fb.heading_remaining == pytest.approx(180.0) and fb.eta > 0.0 and fb.scan_stale
    assert machine().feedback(0.0) is None


def test_log_levels_say_success_and_trouble():
    m = machine()
    running(m)
    actions = m.end("canceled", 1.0)
    assert [a.level for a in actions if isinstance(a, Note)] == [logging.WARNING]
    running(m)
    m.pose(pose(x=8.0), 1.9)  # there: stopped
    assert [a.level for a in m.pose(pose(x=8.0), 2.0) if isinstance(a, Note)] == [logging.INFO]


def test_no_scan_yet_is_not_scans_stopping_and_the_first_scan_is_not_scans_coming_back():
    m = GoalMachine(NavigatorParams(goal_timeout=100.0), WORLD, LIMITS)
    m.pose(pose(), 0.0)
    submit(m, NavigateToRequest(x=9.0, y=5.0, theta=0.0), "caller", 0.0)
    for t in (0.05, 3.0):  # no scan ever: the goal's start said so once, the watchdog says nothing
        m.pose(pose(), t)
        assert notes(m.tick(t)) == []
    m.scan(scan(False, pose()), 3.1)
    assert notes(m.tick(3.15)) == []
    m.pose(pose(), 5.0)
    assert notes(m.tick(5.0)) == ["scans stopped: avoiding only the declared obstacles of the world"]


def _drive_with_scans(m: GoalMachine[str], start: TurtleState, seen: World, until: float) -> tuple[Reply | None, list]:
    """The machine against the kinematics and a 72-beam lidar over ``seen`` (what the scan sees,
    declared or not) every 0.2 s of fake time; the outcome and the turtle's states."""
    from turtlectl.sim.lidar import beam_angles, cast_rays

    angles = beam_angles(-math.pi, math.pi, 72)
    s, now, states, outcome, k = start, 0.0, [], None, 0
    while outcome is None and now < until:
        here = Pose(x=s.x, y=s.y, theta=s.theta)
        if k % 12 == 0:  # 12 steps of 16 ms: about 5 Hz
            ranges = cast_rays(s.x, s.y, s.theta, angles, seen, 10.0)
            scan_msg = LaserScan(
                angle_min=float(angles[0]), angle_max=float(angles[-1]), angle_increment=float(angles[1] - angles[0]),
                range_min=0.0, range_max=10.0, ranges=ranges.tolist(), origin_x=s.x, origin_y=s.y, origin_theta=s.theta,
            )  # fmt: skip
            outcome = next(iter(replies(m.scan(scan_msg, now))), None)
        actions = m.pose(here, now) + m.tick(now)  # the watchdog too: goal_timeout
        outcome = outcome or next(iter(replies(actions)), None)
        cmd = twists(actions)[-1] if twists(actions) else Twist()
        v, w = effective_command(cmd.linear, cmd.angular, 0.0, LIMITS)
        s = step(s, *accelerate(s, v, w, STEP, LIMITS), STEP, seen.size)
        states.append(s)
        now += STEP
        k += 1
    return outcome, states


def test_a_goal_walled_in_by_what_only_the_scan_sees_ends_blocked_not_timeout():
    """Round a ring that only the scan sees, each scan shows a gap that the last one had closed;
    the turtle must not circle it for goal_timeout (30 s) and fail "timeout"."""
    ring = [Obstacle(x=5.5 + 1.2 * math.cos(a * math.pi / 4), y=8.8 + 1.2 * math.sin(a * math.pi / 4), radius=0.5)
            for a in range(8)]  # fmt: skip
    seen = World(size=11.088889, obstacles=ring)
    m = machine(World(size=11.088889), blocked_timeout=5.0, goal_timeout=30.0)
    m.pose(Pose(x=5.5, y=5.0, theta=math.pi / 2), 0.0)
    submit(m, goal(x=5.5, y=8.8, theta=90.0), "caller", 0.0)
    outcome, states = _drive_with_scans(m, TurtleState(x=5.5, y=5.0, theta=math.pi / 2), seen, 31.0)
    assert outcome is not None and outcome.response.reason == "blocked", outcome
    gaps = [min(math.hypot(s.x - o.x, s.y - o.y) - o.radius for o in ring) for s in states]
    assert min(gaps) >= PARAMS.robot_radius - 0.02, min(gaps)


@pytest.mark.parametrize(
    ("rock_y", "start_x", "start_y"),
    [(10.15, 3.0, 10.9), (10.2, 2.0, 10.7), (10.2, 2.0, 10.2), (10.15, 3.0, 10.2)],
)
def test_an_undeclared_obstacle_near_a_wall_is_passed_on_the_open_side_at_a_safe_distance(rock_y, start_x, start_y):
    """An obstacle only the scan sees, about 0.39 m from the top wall.  Planned from the latest
    scan's near-side estimate the path would go over the top, between it and the wall (the
    turtle coming to 0.2 m of it, sometimes ending "blocked" though the way below is open)."""
    rock = Obstacle(x=5.5, y=rock_y, radius=0.5)
    seen = World(size=11.088889, obstacles=[rock])
    m = machine(World(size=11.088889), goal_timeout=30.0)
    m.pose(Pose(x=start_x, y=start_y, theta=0.0), 0.0)
    submit(m, goal(x=8.0, y=start_y, theta=0.0), "caller", 0.0)
    outcome, states = _drive_with_scans(m, TurtleState(x=start_x, y=start_y, theta=0.0), seen, 31.0)
    assert outcome is not None and outcome.response.success, outcome
    gap = min(math.hypot(s.x - rock.x, s.y - rock.y) - rock.radius for s in states)
    assert gap >= PARAMS.robot_radius, gap


@pytest.mark.parametrize(("goal_y", "rock_y"), [(7.0, 8.0), (7.1, 8.0), (7.12, 8.0), (7.14, 8.0)])
def test_a_goal_just_beyond_the_margin_of_something_only_the_scan_sees_is_reached(goal_y, rock_y):
    """A goal 0.5-0.6 m from an obstacle only the scan sees (the turtle keeps 0.45 m) is reached,
    not "blocked" after 10 s: the circles covering the costmap's cells reach ~0.2 m in front
    of what was seen, so the goal could seem to lie within the margin."""
    rock = Obstacle(x=5.5, y=rock_y, radius=0.4)
    m = machine(World(size=11.088889), goal_timeout=30.0)
    m.pose(Pose(x=5.5, y=5.0, theta=math.pi / 2), 0.0)
    submit(m, goal(x=5.5, y=goal_y, theta=90.0), "caller", 0.0)
    outcome, states = _drive_with_scans(
        m, TurtleState(x=5.5, y=5.0, theta=math.pi / 2), World(size=11.088889, obstacles=[rock]), 31.0
    )
    assert outcome is not None and outcome.response.success, outcome
    assert outcome.response.time_taken < 5.0, outcome.response.time_taken  # no wait for a way to open
    gap = min(math.hypot(s.x - rock.x, s.y - rock.y) - rock.radius for s in states)
    assert gap >= PARAMS.robot_radius, gap


def test_a_goal_canceled_by_teleop_says_the_keyboard_took_over():
    """`turtlectl teleop` cancels a running goal with reason "teleop" and its own words,
    which the goal server hands on as the cancel's detail."""
    m = machine()
    m.pose(pose(x=2.0), 0.0)
    submit(m, NavigateToRequest(x=8.0, y=5.0, theta=0.0), "caller", 0.0)
    actions = m.end("teleop", 0.1, TAKEN_OVER)
    reply = next(a for a in actions if isinstance(a, Reply))
    assert (reply.response.reason, reply.response.detail) == (
        "teleop",
        "the keyboard took over (turtlectl teleop)",
    )
