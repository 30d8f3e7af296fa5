"""The latency cost of ``launch --secure``, measured side by side in one run.

Default mode: nodes are peers and talk to each other directly (one hop).  Secure mode: nodes
are logged-in clients of the router, so every message goes through it (two hops), which is
what lets the router check every session.  The figure: one-way latency of ``turtle1/pose``
(62.5 Hz, the simulator's stamp to arrival) at an observer that joins as a node of each mode
does (a peer; a logged-in client; a logged-in client over mutual TLS), over the same number
of samples.

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
from tests.integration.harness import running_system  # noqa: E402
from turtlectl.cli.system.certs import make  # noqa: E402
from turtlectl.messages import Pose, decode  # noqa: E402
from turtlectl.messages.keys import POSE  # noqa: E402
from turtlectl.runtime.client import credentials  # noqa: E402
from turtlectl.runtime.endpoint import TLS_ENV  # noqa: E402
from turtlectl.runtime.session import close_session, node_session_config  # noqa: E402


def pose_latency(secure: bool, seconds: float, tls: Path | None = None) -> list[float]:
    """One-way latencies (s) of turtle1/pose at an observer joined as a node of that mode is."""
    extra = ("--secure",) if secure else ()
    if tls is not None:
        extra += ("--tls", str(tls))
    with running_system(extra_args=extra) as system:
        login = credentials.for_endpoint(system.endpoint) if secure else None  # the observer joins as a node
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
    scratch = Path(tempfile.mkdtemp(prefix="bench-secure-"))
    os.environ[credentials.ENV] = str(scratch / "credentials.json")
    make(scratch / "tls", [])
    os.environ[TLS_ENV] = str(scratch / "tls")
    print(machine())
    modes = {
        "default (peer -> peer)": (False, None),
        "secure (client -> router -> client)": (True, None),
        "secure over mutual TLS": (True, scratch / "tls"),
    }
    rounds: dict[str, list[float]] = {name: [] for name in modes}
    for _ in range(2):  # alternated, so that a noisy moment does not fall on one mode only
        for name, (secure, tls) in modes.items():
            rounds[name] += pose_latency(secure, opts.seconds / 2, tls)
    for name, values in rounds.items():
        print(f"turtle1/pose one-way latency, {name}: {summary(values, 'ms', 1e3)}")
    base = statistics.median(rounds["default (peer -> peer)"])
    for name, values in list(rounds.items())[1:]:
        print(f"{name} / default, median: {statistics.median(values) / base:.2f}x")


if __name__ == "__main__":
    main()
