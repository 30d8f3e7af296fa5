"""Start-up of this checkout against another (the code before a change), alternated in one run:
launch-to-ready (``turtlectl launch`` of the default launch file until each of its four nodes
holds its liveliness token) and ``turtlectl --help`` to its end.  Each checkout runs its own
``.venv/bin/turtlectl`` from its own folder; readiness is watched the same way for both, from a
zenoh session of this process.  Prints medians and percentiles per checkout and the ratio of
medians (this / before): machines here are shared and noisy, compare ratios.

Usage: python bench/startup.py --before ../before [--launches 10] [--helps 15]
(``--before``: a checkout of the code before, e.g. ``git worktree add ../before HEAD~5`` then
``make bytecode`` there.)
"""

from __future__ import annotations

import argparse
import contextlib
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import NamedTuple

import zenoh

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from bench.system import machine, summary  # noqa: E402
from turtlectl.runtime.session import close_session, peer_config  # noqa: E402

NODES = {"sim", "navigator", "status_monitor", "obstacle_detector"}
TOKENS = "@turtlectl/node/**"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def listening(port: int) -> bool:
    """Whether something accepts TCP connections on 127.0.0.1:``port``."""
    try:
        socket.create_connection(("127.0.0.1", port), timeout=0.05).close()
        return True
    except OSError:
        return False


class Ready(NamedTuple):
    session: zenoh.Session  # this process's observer session, on the system's router
    seconds: float  # from starting the launch to every node's token
    pid: int  # the launch's, the leader of its process group


@contextlib.contextmanager
def launched(argv: list[str], cwd: Path, port: int, timeout: float = 30.0) -> Iterator[Ready]:
    """Run ``argv`` (a ``turtlectl launch`` on ``port``) in its own process group; once each of
    its four nodes holds its liveliness token, yield what was seen; then stop it (SIGINT to the
    group, SIGKILL if it lingers)."""
    endpoint = f"tcp/127.0.0.1:{port}"
    seen: set[str] = set()
    done = threading.Event()

    def on_token(sample: zenoh.Sample) -> None:
        if sample.kind == zenoh.SampleKind.PUT:
            seen.add(str(sample.key_expr).split("/")[2])
            if NODES <= seen:
                done.set()

    started = time.monotonic()
    proc = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        while not listening(port):  # the router listens once launch has started it
            if time.monotonic() - started > timeout:
                raise RuntimeError(f"{cwd}: no router at {endpoint}")
            time.sleep(0.002)  # pacing: polling the port (zenoh.open's own retries wait far longer)
        session = zenoh.open(peer_config(endpoint))
        try:
            token_sub = session.liveliness().declare_subscriber(TOKENS, on_token, history=True)
            if not done.wait(timeout):
                raise RuntimeError(f"{cwd}: not ready in {timeout:g} s (seen {sorted(seen)})")
            elapsed = time.monotonic() - started
            token_sub.undeclare()
            yield Ready(session, elapsed, proc.pid)
        finally:
            close_session(session)
    finally:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(15)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def launch_to_ready(checkout: Path, timeout: float = 30.0) -> float:
    """Seconds from starting ``checkout``'s ``turtlectl launch`` to every node's token, then stopped."""
    port = free_port()
    argv = [str(checkout / ".venv" / "bin" / "turtlectl"), "launch", "--port", str(port)]
    with launched(argv, checkout, port, timeout) as ready:
        return ready.seconds


def help_time(checkout: Path) -> float:
    started = time.monotonic()
    subprocess.run([str(checkout / ".venv" / "bin" / "turtlectl"), "--help"], cwd=checkout, capture_output=True)
    return time.monotonic() - started


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", type=Path, required=True, help="a checkout of the code before, with its .venv")
    ap.add_argument("--launches", type=int, default=10, help="launches of each checkout, alternated")
    ap.add_argument("--helps", type=int, default=15, help="runs of --help of each checkout, alternated")
    args = ap.parse_args()
    checkouts = {"this": ROOT, "before": args.before.resolve()}
    print(f"machine: {machine()}")
    for what, measure, runs in (("launch-to-ready", launch_to_ready, args.launches), ("--help", help_time, args.helps)):
        times: dict[str, list[float]] = {name: [] for name in checkouts}
        for _ in range(runs):
            for name, checkout in checkouts.items():  # alternated: the machine's noise falls on both
                times[name].append(measure(checkout))
        for name in checkouts:
            print(f"{what} {name:>6}: {summary(times[name], 'ms', 1e3)}")
        ratio = sorted(times["this"])[runs // 2] / sorted(times["before"])[runs // 2]
        print(f"{what} ratio of medians this/before: {ratio:.3f}")


if __name__ == "__main__":
    main()
