"""The latency cost of ``launch --secure``, measured side by side in one run.

Default mode: nodes are peers and talk to each other directly (one hop).  Secure mode: nodes
are logged-in clients of the router, so every message goes through it (two hops), which is
what lets the router check every session.  The figure: one-way latency of ``turtle1/pose``
(62.5 Hz, the simulator's stamp to arrival) at an observer that joins as a node of each mode
does (a peer; a logged-in client), over the same number of samples.

Usage: python bench/secure.py [--seconds S]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import zenoh

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from bench.system import Stamped, machine, summary  # noqa: E402
from cli import credentials  # noqa: E402
from messages import Pose, decode  # noqa: E402
from messages.keys import POSE  # noqa: E402
from runtime.session import close_session, node_session_config  # noqa: E402
from tests.integration.harness import running_system  # noqa: E402


def pose_latency(secure: bool, seconds: float) -> list[float]:
    """One-way latencies (s) of turtle1/pose at an observer joined as a node of that mode is."""
    with running_system(extra_args=("--secure",) if secure else ()) as system:
        login = credentials.for_endpoint(system.endpoint) if secure else None
        session = zenoh.open(node_session_config(system.endpoint, "", login))
        try:
            observer = Stamped(session, POSE, lambda payload: decode(payload, Pose).stamp)
            time.sleep(seconds)  # the measuring window
            observer.close()
        finally:
            close_session(session)
    return [latency for _, latency in observer.samples[10:]]  # the first few while joining left out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    opts = parser.parse_args()
    os.environ[credentials.ENV] = str(Path(tempfile.mkdtemp(prefix="bench-secure-")) / "credentials.json")
    print(machine())
    rounds = {"default (peer -> peer)": [], "secure (client -> router -> client)": []}
    for _ in range(2):  # alternated, so that a noisy moment does not fall on one mode only
        rounds["default (peer -> peer)"] += pose_latency(False, opts.seconds / 2)
        rounds["secure (client -> router -> client)"] += pose_latency(True, opts.seconds / 2)
    for name, values in rounds.items():
        print(f"turtle1/pose one-way latency, {name}: {summary(values, 'ms', 1e3)}")
    base, secure = (statistics.median(v) for v in rounds.values())
    print(f"secure / default, median: {secure / base:.2f}x")


if __name__ == "__main__":
    main()
