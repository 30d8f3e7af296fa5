"""The web page's cost (``turtlectl web``), in one run: the page server's CPU with no browser, with one
and with three pages open; the frames a page receives and draws each second against the pose rate;
and how much later than a pose's stamp the page draws it.  Two turtles drive goals back to back all the
while (every pose changes).  The configurations alternate over the rounds (0, 1, 3, 0, 1, 3, ...), the
machine being shared and noisy.

    .venv/bin/python bench/web.py [--rounds 3] [--seconds 10]

The pages are Debian's Chromium (tests/integration/browser.py finds it), headless, one browser with a
context per page (each page its own renderer).  Prints one JSON object per round and configuration, then
medians over the rounds with the machine.  Latency: the pose's stamp (the simulator's wall clock) to the
animation frame that drew it (the browser's wall clock, performance.timeOrigin + now): one machine, one
clock.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench.system import machine  # noqa: E402
from tests.integration.browser import CHROMIUM_FLAGS, chromium_path  # noqa: E402
from tests.integration.harness import System, free_port  # noqa: E402
from turtlectl import Client  # noqa: E402
from turtlectl.runtime.client.errors import TurtlectlError  # noqa: E402

TICKS = 100
POSE_RATE = 62.5  # Hz: the simulator's pose rate
PAGES = (0, 1, 3)
LANES = {"turtle1": ((2.5, 2.5), (8.5, 2.5)), "turtle2": ((2.5, 8.0), (8.5, 8.0))}  # m: each turtle's two ends


def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS  # utime + stime


def drive(endpoint: str, turtle: str, stop: threading.Event) -> None:
    """Goals back to back between the turtle's two ends until ``stop``."""
    with Client(endpoint, turtle=turtle) as client:
        ends = LANES[turtle]
        i = 0
        while not stop.is_set():
            x, y = ends[i % 2]
            try:
                client.goto(x, y, 0.0 if i % 2 == 0 else 180.0, timeout=20.0)
            except TurtlectlError:
                pass  # a goal refused or canceled: the next one
            i += 1


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))] if ordered else float("nan")


def ready(page, timeout: float = 20.0) -> None:  # type: ignore[no-untyped-def]
    """Wait until the page draws both turtles (polled: the page's CSP forbids Playwright's string predicates)."""
    deadline = time.monotonic() + timeout
    while not page.evaluate("!!(window.turtlectl && turtlectl.model.poses.turtle2)"):
        if time.monotonic() > deadline:
            raise TimeoutError(f"the page at {page.url} drew no turtle2 within {timeout} s")
        page.wait_for_timeout(100)


def measure(pages: list, pid: int, seconds: float) -> dict:  # type: ignore[type-arg]
    """The server's CPU (% of one core) and each page's rates and latencies over ``seconds``."""
    for page in pages:
        page.evaluate("turtlectl.model.stats.latencies.length = 0")
    before = [page.evaluate("[turtlectl.model.stats.frames, turtlectl.model.stats.drawn]") for page in pages]
    cpu0, t0 = cpu_seconds(pid), time.monotonic()
    deadline = t0 + seconds
    while time.monotonic() < deadline:  # the pages' loops run while Playwright waits
        if pages:
            pages[0].wait_for_timeout(200)
        else:
            time.sleep(0.2)
    elapsed = time.monotonic() - t0
    cpu = 100 * (cpu_seconds(pid) - cpu0) / elapsed
    after = [page.evaluate("[turtlectl.model.stats.frames, turtlectl.model.stats.drawn]") for page in pages]
    latencies = [v for page in pages for v in page.evaluate("turtlectl.model.stats.latencies")]
    return {
        "pages": len(pages),
        "server_cpu_percent": round(cpu, 1),
        "frames_per_s": [round((a[0] - b[0]) / elapsed, 1) for a, b in zip(after, before, strict=True)],
        "draws_per_s": [round((a[1] - b[1]) / elapsed, 1) for a, b in zip(after, before, strict=True)],
        "latency_ms": {
            "p50": round(percentile(latencies, 0.5), 1),
            "p90": round(percentile(latencies, 0.9), 1),
            "p99": round(percentile(latencies, 0.99), 1),
            "n": len(latencies),
        }
        if latencies
        else None,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=10.0)
    options = parser.parse_args()
    from playwright.sync_api import sync_playwright

    port = free_port()
    system = System(extra_args=("--web", str(port)))
    stop = threading.Event()
    rows: list[dict] = []
    try:
        pids = system.wait_ready(("sim", "navigator", "status_monitor", "obstacle_detector", "web"))
        system.run_cli("spawn", "2.5", "8", "0", "--name", "turtle2", "--connect", system.endpoint)
        for turtle in LANES:
            threading.Thread(target=drive, args=(system.endpoint, turtle, stop), daemon=True).start()
        with sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path=chromium_path(), args=list(CHROMIUM_FLAGS))
            url = f"http://127.0.0.1:{port}/"
            for round_ in range(options.rounds):
                for count in PAGES:
                    contexts = [browser.new_context(viewport={"width": 1280, "height": 800}) for _ in range(count)]
                    pages = [context.new_page() for context in contexts]
                    for page in pages:
                        page.goto(url)
                        ready(page)
                    time.sleep(1.0)  # the pages settled (their first frames drawn) before the window opens
                    row = {"round": round_, **measure(pages, pids["web"], options.seconds)}
                    print(json.dumps(row), flush=True)
                    rows.append(row)
                    for context in contexts:
                        context.close()
            browser.close()
    finally:
        stop.set()
        system.kill_everything()
    summary = {"machine": machine(), "pose_rate_hz": POSE_RATE, "seconds": options.seconds, "rounds": options.rounds}
    for count in PAGES:
        mine = [r for r in rows if r["pages"] == count]
        entry: dict = {"server_cpu_percent_median": statistics.median(r["server_cpu_percent"] for r in mine)}
        if count:
            entry["frames_per_s_median"] = statistics.median(v for r in mine for v in r["frames_per_s"])
            entry["draws_per_s_median"] = statistics.median(v for r in mine for v in r["draws_per_s"])
            for q in ("p50", "p90", "p99"):
                entry[f"latency_ms_{q}_median"] = statistics.median(r["latency_ms"][q] for r in mine)
        summary[f"{count}_pages"] = entry
    print(json.dumps(summary, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
