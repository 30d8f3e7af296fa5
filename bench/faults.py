"""Fault-injection benchmark: how long the real system takes to be whole again.

- kill -9 of each respawning node while idle: time until its new liveliness
  token appears, and until a goal succeeds again;
- kill -9 of the navigator in the middle of a goal: time until the turtle is at rest;
- restart of the router (`turtlectl router`, nodes joined with `launch --connect`):
  time from the new router to every node listed again;
- kill -9 of the supervisor: time until none of its children is left.

Usage: python bench/faults.py [--rounds N]
"""

from __future__ import annotations

import argparse
import os
import signal
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.integration.harness import NODES, System, pid_alive, running_system  # noqa: E402
from tests.integration.test_faults import Router  # noqa: E402  (the tests' restartable router)


def wait(condition, timeout: float, what: str) -> float:
    start = time.monotonic()
    while not condition():
        if time.monotonic() - start > timeout:
            raise SystemExit(f"timed out waiting for {what}")
        time.sleep(0.005)  # pacing: polling under a deadline
    return time.monotonic() - start


def show(label: str, values: list[float]) -> None:
    each = ", ".join(f"{v:.2f}" for v in values)
    print(f"{label:62s} median {statistics.median(values):6.2f} s  max {max(values):6.2f} s  rounds: {each}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    with running_system() as system:
        for node in ("navigator", "status_monitor", "obstacle_detector"):
            token, whole = [], []
            for _ in range(args.rounds):
                old = system.alive[node]
                os.kill(old, signal.SIGKILL)
                killed = time.monotonic()
                system.wait_until(lambda o=old, n=node: system.alive.get(n, o) != o, 20.0, f"{node} back")
                token.append(time.monotonic() - killed)
                response, _, _ = system.navigate(4.0, 4.0 + len(token) % 2, 0.0)
                assert response.success, response
                whole.append(time.monotonic() - killed)
            show(f"kill -9 {node}: new token (backoff 1, 2, 4 s)", token)
            show(f"kill -9 {node}: a ~1 s goal has completed again", whole)

        at_rest = []
        for _ in range(args.rounds):
            system.teleport(1.0, 5.5, 0.0)
            goal = subprocess.Popen(
                [sys.executable, "-m", "turtlectl.cli", "goto", "10", "5.5", "0", "--connect", system.endpoint],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
            system.wait_moving(1.0)
            old = system.alive["navigator"]
            os.kill(old, signal.SIGKILL)
            killed = time.monotonic()
            system.wait_stopped(10.0)
            at_rest.append(time.monotonic() - killed)
            goal.wait(10)
            system.wait_until(lambda o=old: system.alive.get("navigator", o) != o, 20.0, "navigator back")
        show("kill -9 navigator mid-goal: turtle at rest (1 s cmd timeout)", at_rest)

    router = Router()
    router.start()
    try:
        with running_system(join=router.endpoint) as system:
            back = []
            for _ in range(args.rounds):
                router.kill()
                router.start()
                restarted = time.monotonic()
                while True:
                    result = system.run_cli("list", "--json")
                    if result.returncode == 0 and all(f'"name":"{n}"' in result.stdout for n in NODES):
                        break
                back.append(time.monotonic() - restarted)
            show("router restart: every node listed again (via the CLI)", back)
    finally:
        router.kill()

    orphans_gone = []
    for _ in range(args.rounds):
        system = System()
        try:
            pids = system.wait_ready()
            os.killpg(system.proc.pid, signal.SIGKILL)
            killed = time.monotonic()
            wait(lambda p=pids: not any(pid_alive(x) for x in p.values()), 10.0, "children gone")
            orphans_gone.append(time.monotonic() - killed)
        finally:
            system.kill_everything()
    show("kill -9 supervisor: every child gone", orphans_gone)


if __name__ == "__main__":
    main()
