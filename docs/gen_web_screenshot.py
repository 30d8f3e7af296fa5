"""The screenshot of docs/how-to/web.md, ``docs/images/web.png``: the example fleet (three turtles, each
with its nodes), two of them on a goal, its page open in Debian's Chromium (headless, 1280x800) with the topics panel echoing one.

    .venv/bin/python docs/gen_web_screenshot.py

Run by hand when the page changes; nothing checks the picture against the page.
"""

from __future__ import annotations

import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests.integration.browser import browser_page, wait_for  # noqa: E402
from tests.integration.harness import System, free_port  # noqa: E402
from turtlectl import Client  # noqa: E402
from turtlectl.runtime.client.errors import TurtlectlError  # noqa: E402

OUT = ROOT / "docs" / "images" / "web.png"


def drive_to(endpoint: str, turtle: str, x: float, y: float, theta: float) -> None:
    try:
        with Client(endpoint, turtle=turtle) as client:
            client.goto(x, y, theta)
    except TurtlectlError:
        pass  # the picture was taken and the system stopped under the goal


def main() -> int:
    port = free_port()
    system = System(ROOT / "examples" / "fleet" / "launch.toml", extra_args=("--web", str(port)))
    try:
        system.wait_ready(("sim", "turtle2/navigator", "web"))
        with Client(system.endpoint, turtle="turtle1") as client:
            client.goto(3.0, 2.5, 180.0)  # a trail to draw
        goals = [
            threading.Thread(target=drive_to, args=(system.endpoint, "turtle1", 9.0, 5.5, 90.0), daemon=True),
            threading.Thread(target=drive_to, args=(system.endpoint, "turtle2", 9.5, 8.0, 0.0), daemon=True),
        ]
        with browser_page(f"http://127.0.0.1:{port}/", viewport=(1280, 800)) as page:
            wait_for(page, "turtlectl.model.poses.turtle2 && turtlectl.model.graph.topics.length > 0", 20)
            page.click("#tabs button[data-tab=topics]")
            page.click("#topics tr[data-key='robot/status'] td")
            for thread in goals:
                thread.start()
            wait_for(page, "turtlectl.model.goals.turtle1 && turtlectl.model.goals.turtle2", 20)
            time.sleep(1.5)  # the picture: well under way
            OUT.parent.mkdir(exist_ok=True)
            page.screenshot(path=str(OUT))
    finally:
        system.kill_everything()
    print(f"wrote {OUT.relative_to(ROOT)} ({OUT.stat().st_size // 1024} KiB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
