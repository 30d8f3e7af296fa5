"""A node module for the zygote's tests: what ``main()`` does comes from ZYGOTE_TEST."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time


def main() -> None:
    what = os.environ.get("ZYGOTE_TEST", "")
    if what.startswith("exit:"):
        print("about to exit", flush=True)
        print("on stderr", file=sys.stderr)
        sys.exit(int(what[5:]))
    if what == "raise":
        raise RuntimeError("raised in main")
    if what == "describe":
        facts = {
            "pid": os.getpid(),
            "pgid": os.getpgid(0),
            "ppid": os.getppid(),
            "env": {k: v for k, v in os.environ.items() if k.startswith(("ZYGOTE_", "TURTLECTL_"))},
            "sigint": signal.getsignal(signal.SIGINT) is signal.default_int_handler,
            "sigterm": signal.getsignal(signal.SIGTERM) == signal.SIG_DFL,
            "sigchld": signal.getsignal(signal.SIGCHLD) == signal.SIG_DFL,
            "mask": sorted(int(s) for s in signal.pthread_sigmask(signal.SIG_BLOCK, [])),
            "stdin": os.read(0, 10).decode(),
            "comm": open("/proc/self/comm").read().strip(),
            "fds": sorted(int(fd) for fd in os.listdir("/proc/self/fd")),
        }
        print(json.dumps(facts))
        return
    if what == "family":  # a child of its own, then wait to be signalled
        grandchild = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])  # pacing: ok
        print(grandchild.pid, flush=True)
    time.sleep(60)  # pacing: ok (stays until signalled)
