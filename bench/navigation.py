"""Navigation benchmark: a fixed, seeded set of goals over the whole world, each from
a known start pose (teleport), through the real system.

Reports success rate, worst position and heading errors, time per goal, and the
ratio of each goal's time to the rotate-drive-rotate time under the same limits
(turn to face the goal, drive straight, turn to the final heading, each with a
trapezoidal speed profile; nodes.control.rotate_drive_rotate_time).

Usage: python bench/navigation.py [--goals N] [--seed S]
"""

from __future__ import annotations

import argparse
import math
import random
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from cli.launchfile import load_launch  # noqa: E402
from nodes.control import Pose2D, rotate_drive_rotate_time  # noqa: E402
from tests.integration.harness import NODES, running_system  # noqa: E402  (the tests' launcher)

LAUNCH = ROOT / "bench" / "navigation.toml"


def pct(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(q / 100 * (len(ordered) - 1))))]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--goals", type=int, default=60)
    ap.add_argument("--seed", type=int, default=2026)
    args = ap.parse_args()
    plan = load_launch(LAUNCH)
    size, limits = plan.launch.world.size, plan.launch.limits
    rng = random.Random(args.seed)
    cases = [
        (
            (rng.uniform(0, size), rng.uniform(0, size), rng.uniform(-math.pi, math.pi)),
            (rng.uniform(0, size), rng.uniform(0, size), rng.uniform(0.0, 360.0)),
        )
        for _ in range(args.goals)
    ]
    rows = []
    with running_system(LAUNCH, NODES) as system:
        for start, goal in cases:
            system.teleport(*start)
            response, elapsed, _ = system.navigate(*goal, timeout=30.0)
            baseline = rotate_drive_rotate_time(Pose2D(*start), Pose2D(goal[0], goal[1], math.radians(goal[2])), limits)
            rows.append((response, elapsed, baseline))

    ok = [r for r, _, _ in rows if r.success]
    times = [r.time_taken for r, _, _ in rows]
    ratios = [r.time_taken / b for r, _, b in rows if b > 0]
    print(f"limits: {limits}")
    print(
        "| goals | success | max position error | max heading error | mean time | p95 time |"
        " mean ratio | p95 ratio | max ratio |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    print(
        f"| {len(rows)} | {100.0 * len(ok) / len(rows):.0f} % | "
        f"{max(r.position_error for r, _, _ in rows) * 1000:.1f} mm | "
        f"{max(r.heading_error for r, _, _ in rows):.2f} deg | {statistics.mean(times):.3f} s | "
        f"{pct(times, 95):.3f} s | {statistics.mean(ratios):.3f} | {pct(ratios, 95):.3f} | {max(ratios):.3f} |"
    )
    failures = [(r.reason, g) for (r, _, _), (_, g) in zip(rows, cases, strict=False) if not r.success]
    if failures:
        print(f"failures: {failures}")
    client_gap = [e - r.time_taken for r, e, _ in rows]
    print(f"client time - time_taken: p50 {pct(client_gap, 50) * 1000:.2f} ms, max {max(client_gap) * 1000:.2f} ms")


if __name__ == "__main__":
    main()
