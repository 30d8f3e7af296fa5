"""Navigation benchmark: fixed, seeded sets of goals, each from a known start pose
(teleport), through the real system.

Set "free" (bench/navigation.toml, no obstacles): success rate, worst position and
heading errors, time per goal, and the ratio of each goal's time to the
rotate-drive-rotate time under the same limits (turn to face the goal, drive straight,
turn to the final heading, each with a trapezoidal speed profile;
nodes.control.rotate_drive_rotate_time).  Straight-line goals: target mean ratio <= 0.85.

Errors are measured where the turtle comes to rest (the first pose with both speeds zero
after the response), not in the response alone: a goal is reached when the turtle at rest
is within the tolerances (1 cm, 0.5 deg by default).  "response vs rest" is how far the
response's final pose is from that rest pose (0 when the navigator answers at rest).  "at rest"
times each goal from the call to the first pose at rest (client clock): the time a turtle
really takes, whatever the response says.

Set "world" (launch.toml, the default world and its three obstacles): goals, half spread
over the world and half behind an obstacle as seen from their start (starts and goals
within robot_radius + clearance of an obstacle left out),
reporting success rate, the minimum clearance to any obstacle over the whole run (every
pose: the distance from the turtle's centre to the obstacle's surface, never below
robot_radius), mean and p95 time, and the ratio of each goal's time to a careful driver
on the shortest path (rotate-drive-rotate generalised to the path, nodes.control.path_time):
target 100 % and mean ratio <= 1.0.

Simulated time (``--time-scale F``): the free set twice in one run, at 1x and with
``launch --time-scale F`` (the simulator F times as fast, every node on its clock), goal by
goal: the same success, errors within the tolerances, time_taken (simulated s at F) against
1x's, and the wall-clock time each run of the set took.

Usage: python bench/navigation.py [--set free|world|both] [--goals N] [--world-goals M] [--seed S] [--time-scale F]
"""

from __future__ import annotations

import argparse
import math
import queue
import random
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import msgspec  # noqa: E402

from tests.integration.harness import NODES, running_system  # noqa: E402  (the tests' launcher)
from turtlectl.cli.system.launchfile import load_launch  # noqa: E402
from turtlectl.messages import Pose, decode  # noqa: E402
from turtlectl.messages.keys import POSE  # noqa: E402
from turtlectl.nodes.control import Pose2D, path_time, rotate_drive_rotate_time  # noqa: E402
from turtlectl.nodes.params import NavigatorParams  # noqa: E402
from turtlectl.nodes.planner import containing, inflate, shortest_path  # noqa: E402

FREE = ROOT / "bench" / "navigation.toml"
WORLD = ROOT / "launch.toml"


class Poses:
    """Every pose with its arrival time (monotonic s), from a subscriber of the bench's own."""

    def __init__(self, system):
        self.queue: queue.SimpleQueue[tuple[float, Pose]] = queue.SimpleQueue()
        self.sub = system.session.declare_subscriber(
            POSE, lambda s: self.queue.put((time.monotonic(), decode(s.payload.to_bytes(), Pose)))
        )

    def take(self) -> list[tuple[float, Pose]]:
        out = []
        while not self.queue.empty():
            out.append(self.queue.get())
        return out


def drive(system, poses: Poses, goal: tuple[float, float, float], timeout: float):
    """Run a goal, then wait for the turtle at rest: (response, client seconds, feedback,
    (position error m, heading error deg, gap between the response's final pose and the rest
    pose m or deg), seconds from the call to the first pose at rest, the poses seen)."""
    poses.take()
    started = time.monotonic()
    response, elapsed, feedback = system.navigate(*goal, timeout=timeout)
    system.wait_stopped()
    seen = poses.take()
    moving = [k for k, (_, p) in enumerate(seen) if p.linear_velocity != 0.0 or p.angular_velocity != 0.0]
    rest_at, pose = seen[moving[-1] + 1] if moving and moving[-1] + 1 < len(seen) else seen[-1]
    gx, gy, gt = goal
    errors = (
        math.hypot(pose.x - gx, pose.y - gy),
        abs((math.degrees(pose.theta) - gt + 180.0) % 360.0 - 180.0),
        max(
            math.hypot(pose.x - response.x, pose.y - response.y),
            abs((math.degrees(pose.theta) - response.theta + 180.0) % 360.0 - 180.0),
        ),
    )
    return response, elapsed, feedback, errors, max(rest_at - started, elapsed), [p for _, p in seen]


def rest_line(to_rest: list[float], baselines: list[float]) -> str:
    ratios = [t / b for t, b in zip(to_rest, baselines, strict=True) if b > 0]
    return (
        f"at rest (call to the first pose at rest, client clock): mean time {statistics.mean(to_rest):.3f} s, "
        f"mean ratio {statistics.mean(ratios):.3f}, p95 ratio {pct(ratios, 95):.3f}"
    )


def pct(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(q / 100 * (len(ordered) - 1))))]


def free_set(goals: int, seed: int, time_scale: float | None = None) -> tuple[list, list, float]:
    """Run the free set (at ``time_scale`` with ``launch --time-scale``), print its table;
    (rows of (response, client s, baseline s), errors at rest, wall-clock s of the set)."""
    plan = load_launch(FREE)
    size, limits = plan.launch.world.size, plan.launch.limits
    rng = random.Random(seed)
    cases = [
        (
            (rng.uniform(0, size), rng.uniform(0, size), rng.uniform(-math.pi, math.pi)),
            (rng.uniform(0, size), rng.uniform(0, size), rng.uniform(0.0, 360.0)),
        )
        for _ in range(goals)
    ]
    rows, rest, to_rest = [], [], []
    extra = ("--time-scale", str(time_scale)) if time_scale else ()
    with running_system(FREE, NODES, extra_args=extra) as system:
        poses = Poses(system)
        set_started = time.monotonic()
        for start, goal in cases:
            system.teleport(*start)
            response, elapsed, _, errors, resting, _ = drive(system, poses, goal, 30.0)
            baseline = rotate_drive_rotate_time(Pose2D(*start), Pose2D(goal[0], goal[1], math.radians(goal[2])), limits)
            rows.append((response, elapsed, baseline))
            rest.append(errors)
            to_rest.append(resting)
        wall = time.monotonic() - set_started
        poses.sub.undeclare()

    ok = [r for r, _, _ in rows if r.success]
    times = [r.time_taken for r, _, _ in rows]
    ratios = [r.time_taken / b for r, _, b in rows if b > 0]
    scale = f", --time-scale {time_scale:g} (time_taken in simulated s; client times wall)" if time_scale else ""
    print(f"## set free: {FREE.relative_to(ROOT)}, no obstacles, {len(rows)} goals, seed {seed}{scale}")
    print(f"limits: {limits}")
    print(
        "| goals | success | max position error at rest | max heading error at rest | mean time | p95 time |"
        " mean ratio | p95 ratio | max ratio |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    print(
        f"| {len(rows)} | {100.0 * len(ok) / len(rows):.0f} % | "
        f"{max(p for p, _, _ in rest) * 1000:.1f} mm | "
        f"{max(h for _, h, _ in rest):.2f} deg | {statistics.mean(times):.3f} s | "
        f"{pct(times, 95):.3f} s | {statistics.mean(ratios):.3f} | {pct(ratios, 95):.3f} | {max(ratios):.3f} |"
    )
    failures = [(r.reason, g) for (r, _, _), (_, g) in zip(rows, cases, strict=False) if not r.success]
    if failures:
        print(f"failures: {failures}")
    print(
        f"in the responses: max position error {max(r.position_error for r, _, _ in rows) * 1000:.1f} mm, "
        f"max heading error {max(r.heading_error for r, _, _ in rows):.2f} deg; "
        f"response vs rest: max {max(g for _, _, g in rest):.4f} (m or deg)"
    )
    print(rest_line(to_rest, [b for _, _, b in rows]))
    client_gap = [e - r.time_taken for r, e, _ in rows]
    print(f"client time - time_taken: p50 {pct(client_gap, 50) * 1000:.2f} ms, max {max(client_gap) * 1000:.2f} ms")
    print(f"the set took {wall:.1f} s of wall clock")
    return rows, rest, wall


def compare_time_scales(goals: int, seed: int, factor: float) -> None:
    """The free set at 1x and at ``factor``, goal by goal, in one run."""
    real, real_rest, real_wall = free_set(goals, seed)
    fast, fast_rest, fast_wall = free_set(goals, seed, factor)
    tolerance = NavigatorParams()
    same = sum(1 for (a, _, _), (b, _, _) in zip(real, fast, strict=True) if a.success == b.success)
    within = sum(1 for p, h, _ in fast_rest if p <= tolerance.position_tolerance and h <= tolerance.heading_tolerance)
    ratios = [b.time_taken / a.time_taken for (a, _, _), (b, _, _) in zip(real, fast, strict=True) if a.time_taken > 0]
    print(f"## --time-scale {factor:g} against 1x, free set, {len(real)} goals, seed {seed}")
    print(
        "| same outcome | at rest within tolerances at F | time_taken F / 1x: median | p5 | p95 | wall clock 1x | wall clock F | speed-up |"
    )
    print("|---|---|---|---|---|---|---|---|")
    print(
        f"| {same}/{len(real)} | {within}/{len(fast)} | {statistics.median(ratios):.3f} | {pct(ratios, 5):.3f} | "
        f"{pct(ratios, 95):.3f} | {real_wall:.1f} s | {fast_wall:.1f} s | {real_wall / fast_wall:.2f}x |"
    )


def world_set(goals: int, seed: int) -> None:
    plan = load_launch(WORLD)
    world, limits = plan.launch.world, plan.launch.limits
    nav = msgspec.convert(plan.params["navigator"], NavigatorParams)
    keep = nav.robot_radius + nav.clearance
    circles = inflate(world.obstacles, keep)
    rng = random.Random(seed)

    def free_point() -> tuple[float, float]:
        while True:
            x, y = rng.uniform(0, world.size), rng.uniform(0, world.size)
            if containing(x, y, circles) is None:
                return x, y

    def behind() -> tuple[tuple[float, float], tuple[float, float]]:
        """A start and a goal on either side of one obstacle, 1 to 3 m from it."""
        while True:
            o = rng.choice(world.obstacles)
            a = rng.uniform(-math.pi, math.pi)
            b = a + math.pi + rng.uniform(-0.4, 0.4)
            r1, r2 = o.radius + keep + rng.uniform(0.5, 2.5), o.radius + keep + rng.uniform(0.5, 2.5)
            start = (o.x + r1 * math.cos(a), o.y + r1 * math.sin(a))
            goal = (o.x + r2 * math.cos(b), o.y + r2 * math.sin(b))
            if all(world.contains(*p) and containing(*p, circles) is None for p in (start, goal)):
                return start, goal

    cases = []
    for k in range(goals):  # half spread over the world, half behind an obstacle
        start, goal = (free_point(), free_point()) if k % 2 == 0 else behind()
        cases.append(((*start, rng.uniform(-math.pi, math.pi)), (*goal, rng.uniform(0.0, 360.0))))
    rows, rest, to_rest = [], [], []
    replans: list[int] = []  # per goal: how many times its path was planned again
    with running_system(WORLD, NODES) as system:
        poses = Poses(system)
        for start, goal in cases:
            system.teleport(*start)
            response, elapsed, feedback, errors, resting, seen = drive(system, poses, goal, 40.0)
            rest.append(errors)
            to_rest.append(resting)
            nearest = min(
                (math.hypot(p.x - o.x, p.y - o.y) - o.radius for p in seen for o in world.obstacles), default=math.inf
            )
            path = shortest_path(start[:2], goal[:2], circles, world.size)
            baseline = path_time(start[2], path, math.radians(goal[2]), limits) if path is not None else math.nan
            rows.append((response, baseline, nearest, path))
            replans.append(max((f.replans for f in feedback), default=0))
        poses.sub.undeclare()

    ok = [r for r, _, _, _ in rows if r.success]
    times = [r.time_taken for r, _, _, _ in rows if r.success]
    ratios = [r.time_taken / b for r, b, _, _ in rows if r.success and b > 0]
    detours = sum(1 for *_, p in rows if p is not None and not p.direct)
    print(
        f"## set world: {WORLD.relative_to(ROOT)}, {len(world.obstacles)} obstacles, {len(rows)} goals "
        f"({detours} round an obstacle), seed {seed}; robot_radius {nav.robot_radius:g} m, keep {keep:g} m"
    )
    print(
        "| goals | success | min clearance (robot_radius) | max position error at rest |"
        " max heading error at rest | mean time |"
        " p95 time | mean ratio | p95 ratio | max ratio |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    print(
        f"| {len(rows)} | {100.0 * len(ok) / len(rows):.0f} % | "
        f"{min(n for _, _, n, _ in rows):.3f} m ({nav.robot_radius:g} m) | "
        f"{max(p for (r, *_), (p, _, _) in zip(rows, rest, strict=True) if r.success) * 1000:.1f} mm | "
        f"{max(h for (r, *_), (_, h, _) in zip(rows, rest, strict=True) if r.success):.2f} deg | "
        f"{statistics.mean(times):.3f} s | "
        f"{pct(times, 95):.3f} s | {statistics.mean(ratios):.3f} | {pct(ratios, 95):.3f} | {max(ratios):.3f} |"
    )
    print(
        f"in the responses: max position error {max(r.position_error for r in ok) * 1000:.1f} mm, "
        f"max heading error {max(r.heading_error for r in ok):.2f} deg; "
        f"response vs rest: max {max(g for _, _, g in rest):.4f} (m or deg)"
    )
    print(
        rest_line(
            [t for t, (r, *_) in zip(to_rest, rows, strict=True) if r.success], [b for r, b, _, _ in rows if r.success]
        )
    )
    round_ratios = [r.time_taken / b for r, b, _, p in rows if r.success and p is not None and not p.direct]
    if round_ratios:
        print(f"goals round an obstacle: mean ratio {statistics.mean(round_ratios):.3f}, max {max(round_ratios):.3f}")
    worst = max(
        (k for k, (r, b, _, _) in enumerate(rows) if r.success and b > 0),
        key=lambda k: rows[k][0].time_taken / rows[k][1],
    )
    (sx, sy, sa), (gx, gy, gt) = cases[worst]
    print(
        f"slowest against its baseline: goal {worst}, from ({sx:.2f}, {sy:.2f}, {math.degrees(sa):.0f} deg) "
        f"to ({gx:.2f}, {gy:.2f}, {gt:.0f} deg): {rows[worst][0].time_taken:.3f} s for {rows[worst][1]:.3f} s, "
        f"replanned {replans[worst]} times; goals replanned at all: {sum(1 for n in replans if n)}"
    )
    failures = [(r.reason, s, g) for (r, _, _, _), (s, g) in zip(rows, cases, strict=False) if not r.success]
    if failures:
        print(f"failures: {failures}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", choices=("free", "world", "both"), default="both")
    ap.add_argument("--goals", type=int, default=60, help="goals of the free set")
    ap.add_argument("--world-goals", type=int, default=60, help="goals of the world set (at least 50 for the README)")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--time-scale", type=float, default=None, help="also run the free set at this factor, and compare")
    args = ap.parse_args()
    if args.time_scale:
        compare_time_scales(args.goals, args.seed, args.time_scale)
    elif args.set in ("free", "both"):
        free_set(args.goals, args.seed)
    if args.set in ("world", "both"):
        world_set(args.world_goals, args.seed)


if __name__ == "__main__":
    main()
