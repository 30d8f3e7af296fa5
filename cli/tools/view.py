"""``turtlectl view``: the world drawn live in a terminal, like turtlesim's window over SSH.

``render`` is pure (text lines from the latest messages); ``run_view`` is the
curses shell around it: it subscribes over Zenoh, queues what arrives, and
redraws at 20 frames a second (curses sends only what changed: no flicker).
Keys: c clears the trail, q quits.  Losing the router is shown on the status line.
"""

from __future__ import annotations

import collections
import curses
import locale
import math
import queue
import time

import msgspec
import zenoh

from turtlectl.cli.tools.client import ROUTER_CHECK, router_lost
from turtlectl.cli.tools.format import heading_text
from turtlectl.messages import LaserScan, NavigateToFeedback, Pose, Turtles, TurtleStatus, decode_any
from turtlectl.messages.angles import heading_degrees
from turtlectl.messages.keys import FEEDBACK, FIRST_TURTLE, OBSTACLES, POSE, STATUS, TURTLES
from turtlectl.messages.world import World
from turtlectl.sim.turtles import others as turtles_but

FRAME = 0.05  # s between frames: 20 frames a second
TRAIL = 400  # poses kept for the trail
LEGEND = "o obstacle  * scan hit  . trail  + path  X goal  (c clears the trail)"
ARROWS = "→↗↑↖←↙↓↘"
ASCII_ARROWS = ">/^\\</v\\"


class Scene(msgspec.Struct, kw_only=True):
    """What the view knows: the latest of each message (None until one arrives)."""

    world: World
    pose: Pose | None = None
    status: TurtleStatus | None = None
    scan: LaserScan | None = None
    feedback: NavigateToFeedback | None = None
    turtles: Turtles | None = None  # every turtle (the others are drawn too, and named)
    trail: list[tuple[float, float]] = msgspec.field(default_factory=list)
    router: str = ""  # the endpoint, when the router is lost (shown instead of the pose)


def render(scene: Scene, cols: int, rows: int, unicode: bool = True) -> list[str]:
    """The screen as ``rows`` lines of at most ``cols`` characters: the world in a frame
    (walls), obstacles ``o``, trail ``.``, the goal's path ``+``, laser hits ``*``, goal
    ``X``, the turtle as an arrow along its heading, and at the bottom a legend and two
    status lines."""
    if cols < 20 or rows < 7:
        return ["terminal too small"][:rows]
    size = scene.world.size
    map_rows = rows - 3
    # terminal cells are about twice as tall as wide: two columns per row's height
    scale_y = min((map_rows - 2) / size, (cols - 2) / (2.0 * size))
    scale_x = 2.0 * scale_y
    width, height = max(1, int(size * scale_x)), max(1, int(size * scale_y))
    grid = [[" "] * width for _ in range(height)]

    def cell(x: float, y: float) -> tuple[int, int] | None:
        c, r = int(x * scale_x), height - 1 - int(y * scale_y)
        return (r, min(c, width - 1)) if 0 <= x <= size and 0 <= y <= size and 0 <= r < height else None

    for r in range(height):
        wy = (height - 1 - r + 0.5) / scale_y
        for c in range(width):
            wx = (c + 0.5) / scale_x
            if any(math.hypot(wx - o.x, wy - o.y) <= o.radius for o in scene.world.obstacles):
                grid[r][c] = "o"
    for x, y in scene.trail:
        if (rc := cell(x, y)) is not None and grid[rc[0]][rc[1]] == " ":
            grid[rc[0]][rc[1]] = "."
    fb = scene.feedback
    if fb is not None:
        for (ax, ay), (bx, by) in zip(fb.path, fb.path[1:], strict=False):
            steps = max(1, int(math.hypot((bx - ax) * scale_x, (by - ay) * scale_y) * 2))
            for k in range(steps + 1):
                rc = cell(ax + (bx - ax) * k / steps, ay + (by - ay) * k / steps)
                if rc is not None and grid[rc[0]][rc[1]] in " .":
                    grid[rc[0]][rc[1]] = "+"
    scan = scene.scan
    if scan is not None and all(math.isfinite(v) for v in (scan.origin_x, scan.origin_y, scan.origin_theta)):
        for i, r in enumerate(scan.ranges):  # beam angles are relative to the heading at origin_theta
            if math.isfinite(r):
                a = scan.origin_theta + scan.angle_min + i * scan.angle_increment
                if (rc := cell(scan.origin_x + r * math.cos(a), scan.origin_y + r * math.sin(a))) is not None:
                    grid[rc[0]][rc[1]] = "*"
    if fb is not None and (rc := cell(fb.goal_x, fb.goal_y)) is not None:
        grid[rc[0]][rc[1]] = "X"
    arrows = ARROWS if unicode else ASCII_ARROWS
    for _, x, y, theta in others(scene):  # the other turtles, as turtle1: an arrow along the heading
        if (rc := cell(x, y)) is not None:
            grid[rc[0]][rc[1]] = arrows[int(round(theta / (math.pi / 4))) % 8]
    if scene.pose is not None and (rc := cell(scene.pose.x, scene.pose.y)) is not None:
        grid[rc[0]][rc[1]] = arrows[int(round(scene.pose.theta / (math.pi / 4))) % 8]

    lines = ["+" + "-" * width + "+"] + ["|" + "".join(row) + "|" for row in grid] + ["+" + "-" * width + "+"]
    lines += [""] * (map_rows - len(lines))
    named = ", ".join(f"{n} ({x:.1f}, {y:.1f})" for n, x, y, _ in others(scene))
    lines.append(LEGEND + (f"  | also: {named}" if named else ""))
    lines += status_lines(scene)
    return [line[:cols] for line in lines[:rows]]


def others(scene: Scene) -> list[tuple[str, float, float, float]]:
    """The turtles besides turtle1 (name, x m, y m, theta rad), from the latest ``turtles``."""
    return [] if scene.turtles is None else turtles_but(scene.turtles, but=FIRST_TURTLE)


def status_lines(scene: Scene) -> list[str]:
    """Two lines: where the turtle is and how fast; battery, goal and the keys."""
    if scene.router:
        where = f"no router at {scene.router}: reconnecting (is `turtlectl launch` running?)"
    elif scene.pose is None:
        where = "waiting for turtle1/pose (is the sim running?)"
    else:
        p = scene.pose
        where = (
            f"x {p.x:5.2f} y {p.y:5.2f} heading {heading_text(heading_degrees(p.theta)):>5s} deg | "
            f"speed {p.linear_velocity:5.2f} m/s"
        )
    parts = []
    if scene.status is not None:
        parts.append(f"battery {scene.status.battery:.1f} %")
    fb = scene.feedback
    parts.append(
        f"goal ({fb.goal_x:.2f}, {fb.goal_y:.2f}) {fb.state} {fb.distance_remaining:.2f} m" if fb else "no goal"
    )
    parts.append("q quits")
    return [where, " | ".join(parts)]


def run_view(session: zenoh.Session, world: World, endpoint: str = "") -> None:
    """Draw until q or Ctrl-C; the terminal is restored whatever happens."""
    locale.setlocale(locale.LC_ALL, "")
    unicode = locale.getpreferredencoding(False).lower().replace("-", "") == "utf8"
    inbox: queue.SimpleQueue[tuple[float, bytes]] = queue.SimpleQueue()
    subs = [
        session.declare_subscriber(key, lambda s: inbox.put((time.monotonic(), s.payload.to_bytes())))
        for key in (POSE, STATUS, OBSTACLES, FEEDBACK, TURTLES)
    ]
    scene = Scene(world=world)
    trail: collections.deque[tuple[float, float]] = collections.deque(maxlen=TRAIL)
    feedback_time = 0.0

    def loop(screen: curses.window) -> None:
        nonlocal feedback_time
        curses.curs_set(0)
        screen.timeout(int(FRAME * 1000))
        next_check = 0.0
        while True:
            if time.monotonic() >= next_check:
                next_check = time.monotonic() + ROUTER_CHECK
                scene.router = (endpoint or "the endpoint") if router_lost(session) else ""
            while not inbox.empty():
                arrived, payload = inbox.get_nowait()
                try:
                    msg = decode_any(payload)
                except ValueError:
                    continue
                if isinstance(msg, Pose):
                    scene.pose = msg
                    if not trail or math.hypot(trail[-1][0] - msg.x, trail[-1][1] - msg.y) > 0.05:
                        trail.append((msg.x, msg.y))
                elif isinstance(msg, TurtleStatus):
                    scene.status = msg
                elif isinstance(msg, LaserScan):
                    scene.scan = msg
                elif isinstance(msg, NavigateToFeedback):
                    scene.feedback, feedback_time = msg, arrived
                elif isinstance(msg, Turtles):
                    scene.turtles = msg
            if scene.feedback is not None and time.monotonic() - feedback_time > 0.5:
                scene.feedback = None  # the goal ended
            scene.trail = list(trail)
            rows, cols = screen.getmaxyx()
            screen.erase()
            for i, line in enumerate(render(scene, cols, rows, unicode)):
                try:
                    screen.addstr(i, 0, line)
                except curses.error:  # writing the bottom-right cell raises; the text is drawn
                    pass
            screen.refresh()
            key = screen.getch()  # waits up to one frame
            if key in (ord("q"), ord("Q")):
                return
            if key in (ord("c"), ord("C")):
                trail.clear()
            if key == curses.KEY_RESIZE:
                screen.clear()  # repaint the whole terminal on the next frame

    try:
        curses.wrapper(loop)
    except KeyboardInterrupt:
        pass
    finally:
        for sub in subs:
            sub.undeclare()
