"""A navigator that serves ``navigate_to`` only: feedback 10 times a second for as long as
the caller waits (up to a minute), never a response, no ``navigate_to/cancel``, no
caller-gone rule.  An old or foreign navigator, as a client may meet one.

``python -m tests.integration.fake_navigator ENDPOINT [silent-cancel]``: with
``silent-cancel`` it also serves ``navigate_to/cancel`` but never answers.  It prints
"goal" for each goal it takes; the liveliness token ``fake/navigator`` says it serves.
"""

from __future__ import annotations

import sys
import threading
import time

import zenoh

from turtlectl.messages import NavigateToFeedback, encode, encoding_for
from turtlectl.messages.keys import CANCEL, NAVIGATE_TO
from turtlectl.runtime.session import client_config

HELD: list[zenoh.Query] = []  # cancels never answered (silent-cancel): kept, so never ended


def feed(query: zenoh.Query) -> None:
    print("goal", flush=True)
    started = time.monotonic()
    try:
        while time.monotonic() - started < 60.0:
            elapsed = time.monotonic() - started
            feedback = NavigateToFeedback(
                state="driving",
                distance_remaining=5.0,
                heading_remaining=0.0,
                eta=5.0,
                elapsed=elapsed,
                x=1,
                y=1,
                theta=0,
            )
            query.reply(NAVIGATE_TO, encode(feedback), encoding=zenoh.Encoding(encoding_for(NavigateToFeedback)))
            time.sleep(0.1)  # pacing: the feedback rate
    except zenoh.ZError:  # the caller went away
        pass
    finally:
        query.drop()


def main() -> None:
    endpoint = sys.argv[1]
    session = zenoh.open(client_config(endpoint, 3.0))
    queryables = [
        session.declare_queryable(NAVIGATE_TO, lambda q: threading.Thread(target=feed, args=(q,), daemon=True).start())
    ]
    if sys.argv[2:] == ["silent-cancel"]:
        queryables.append(session.declare_queryable(CANCEL, HELD.append))
    token = session.liveliness().declare_token("fake/navigator")
    try:
        sys.stdin.read()  # until the test closes our stdin (or kills us)
    finally:
        token.undeclare()
        session.close()


if __name__ == "__main__":
    main()
