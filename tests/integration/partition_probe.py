"""A watcher run inside a host's network namespace (``python -m tests.integration.partition_probe
ENDPOINT KEY...``): a client of the router at ENDPOINT that notes when each sample on each KEY
arrives (``time.monotonic()``, one clock for every process of the machine, namespaces or not).

It prints ``ready`` once every KEY has delivered a sample.  Each ``mark`` line on its stdin
starts a watch: it prints ``seen KEY T`` for the first sample of each KEY arriving after it (T:
its arrival).  When its stdin ends it prints the arrivals as one JSON line ``{key: [t, ...]}``.
"""

from __future__ import annotations

import json
import sys
import threading
import time

import zenoh

from turtlectl.runtime.session import client_config, close_session


def main() -> None:
    endpoint, *keys = sys.argv[1:]
    arrivals: dict[str, list[float]] = {key: [] for key in keys}
    seen = threading.Event()
    watched: set[str] = set()

    def noter(key: str):
        def on_sample(_sample: zenoh.Sample) -> None:
            now = time.monotonic()
            if key in watched:
                watched.discard(key)
                print(f"seen {key} {now}", flush=True)
            arrivals[key].append(now)
            if all(arrivals.values()):
                seen.set()

        return on_sample

    session = zenoh.open(client_config(endpoint, 10.0))
    subscribers = [session.declare_subscriber(key, noter(key)) for key in keys]
    if not seen.wait(60):
        print("never saw " + ", ".join(k for k, v in arrivals.items() if not v), flush=True)
        sys.exit(1)
    print("ready", flush=True)
    for line in sys.stdin:  # until the test is done with the fault
        if line.strip() == "mark":
            watched.update(keys)
    for subscriber in subscribers:
        subscriber.undeclare()
    print(json.dumps(arrivals), flush=True)
    close_session(session)


if __name__ == "__main__":
    main()
