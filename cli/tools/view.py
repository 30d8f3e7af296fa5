"""``turtlectl view``: the world drawn live in a terminal, like turtlesim's window over SSH.

``render`` is pure (text lines from the latest messages); ``run_view`` is the
curses shell around it: it subscribes over Zenoh, queues what arrives, and
redraws at 20 frames a second (curses sends only what changed: no flicker).
Keys: c clears the trails, q quits.  Losing the router is shown on the status line (the
one behaviour of every long-running tool: cli.tools.routerwatch).  The world is asked again
every WORLD_PERIOD s, so a world that appears after the view started (a simulator launched,
a recording played: ``play`` answers ``turtlectl/world`` with the recorded one) or changes is
drawn.
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

from turtlectl.cli.tools.format import heading_text
from turtlectl.cli.tools.routerwatch import watch
from turtlectl.messages import LaserScan, NavigateToFeedback, Pose, Turtles, TurtleStatus, decode_any
from turtlectl.messages.angles import heading_degrees
from turtlectl.messages.keys import (
    FEEDBACK,
    FIRST_TURTLE,
    OBSTACLES,
    POSE,
    STATUS,
    TURTLES,
    WORLD_KEY,
    resolve,
    turtle_of,
)
from turtlectl.messages.world import World
from turtlectl.runtime.client import presence
from turtlectl.runtime.client.session import live_turtle_namespace
from turtlectl.sim.turtles import others as turtles_but

FRAME = 0.05  # s between frames: 20 frames a second
TRAIL = 400  # poses kept for each turtle's trail
TRAIL_STEP = 0.05  # m between two trail positions
GOAL_LIFETIME = 0.5  # s a goal stays drawn after its last feedback
WORLD_PERIOD = 2.0  # s between two questions for the world (it may appear or change while the view runs)
OTHERS_FEEDBACK = "*/" + FEEDBACK  # another turtle's navigator's: turtle2/navigate_to/feedback
LEGEND = "o obstacle  * scan hit  . trail  + path  X goal  (c clears the trail)"
ARROWS = "→↗↑↖←↙↓↘"
ASCII_ARROWS = ">/^\\</v\\"


class Scene(msgspec.Struct, kw_only=True):
    """What the view knows: the latest of each message (None until one arrives)."""

    world: World
    turtle: str = FIRST_TURTLE  # the turtle followed (its pose, scan, status and goal); the others named
    pose: Pose | None = None
    status: TurtleStatus | None = None
    scan: LaserScan | None = None
    feedback: NavigateToFeedback | None = None
    turtles: Turtles | None = None  # every turtle (the others are drawn too, and named)
    trail: list[tuple[float, float]] = msgspec.field(default_factory=list)
    trails: dict[str, list[tuple[float, float]]] = msgspec.field(default_factory=dict)  # the others', by name
    goals: dict[str, NavigateToFeedback] = msgspec.field(default_factory=dict)  # the others' running goals
    router: str = ""  # the endpoint, when the router is lost (shown instead of the pose)


def render(scene: Scene, cols: int, rows: int, unicode: bool = True) -> list[str]:
    """The screen as ``rows`` lines of at most ``cols`` characters: the world in a frame
    (walls), obstacles ``o``, trail ``.``, the goal's path ``+``, laser hits ``*``, goal
    ``X``, the turtle as an arrow along its heading, and at the bottom a legend and two
    status lines.  The other turtles (from ``turtles``) are drawn as the followed one is, with
    their trails and their running goals (a goal's path and ``X``), each named beside its arrow
    where its whole name fits in open map (``place_label``) and beside the legend."""
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
    for trail in (scene.trail, *scene.trails.values()):
        for x, y in trail:
            if (rc := cell(x, y)) is not None and grid[rc[0]][rc[1]] == " ":
                grid[rc[0]][rc[1]] = "."
    fb = scene.feedback
    goals = [g for g in (fb, *scene.goals.values()) if g is not None]
    for goal in goals:
        for (ax, ay), (bx, by) in zip(goal.path, goal.path[1:], strict=False):
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
    for goal in goals:
        if (rc := cell(goal.goal_x, goal.goal_y)) is not None:
            grid[rc[0]][rc[1]] = "X"
    arrows = ARROWS if unicode else ASCII_ARROWS
    for _, x, y, theta in others(scene):  # the other turtles, as turtle1: an arrow along the heading
        if (rc := cell(x, y)) is not None:
            grid[rc[0]][rc[1]] = arrows[int(round(theta / (math.pi / 4))) % 8]
    if scene.pose is not None and (rc := cell(scene.pose.x, scene.pose.y)) is not None:
        grid[rc[0]][rc[1]] = arrows[int(round(scene.pose.theta / (math.pi / 4))) % 8]
    for name, x, y, _ in others(scene):  # each other turtle's name beside its arrow, where the map is open
        if (rc := cell(x, y)) is not None:
            place_label(grid, rc[0], rc[1], name)

    lines = ["+" + "-" * width + "+"] + ["|" + "".join(row) + "|" for row in grid] + ["+" + "-" * width + "+"]
    lines += [""] * (map_rows - len(lines))
    named = ", ".join(
        f"{n} ({x:.1f}, {y:.1f})" + (f" goal ({g.goal_x:.1f}, {g.goal_y:.1f})" if (g := scene.goals.get(n)) else "")
        for n, x, y, _ in others(scene)
    )
    lines.append(LEGEND + (f"  | also: {named}" if named else ""))
    lines += status_lines(scene)
    return [line[:cols] for line in lines[:rows]]


OPEN = " .+"  # cells a label may cover: open map, a trail, a path


def place_label(grid: list[list[str]], row: int, col: int, name: str) -> bool:
    """Write ``name`` beside the arrow at (``row``, ``col``): to its right, else to its left,
    only whole, only over open cells (``OPEN``) and with an open cell or the frame on each side,
    so that labels never overwrite each other, an arrow or an obstacle, nor run into one
    another ("turtle2turtle3").  False (nothing written) where it does not fit: the legend
    names every turtle anyway."""
    line = grid[row]
    for start in (col + 1, col - len(name)):
        end = start + len(name)
        if start < 0 or end > len(line):
            continue
        if all(c in OPEN for c in line[start:end]) and _apart(line, start, end, col):
            line[start:end] = list(name)
            return True
    return False


def _apart(line: list[str], start: int, end: int, arrow: int) -> bool:
    """True if the cells just outside [start, end) are open, the frame, or the label's own arrow."""
    return all(i < 0 or i >= len(line) or i == arrow or line[i] in OPEN for i in (start - 1, end))


def others(scene: Scene) -> list[tuple[str, float, float, float]]:
    """The turtles besides the followed one (name, x m, y m, theta rad), from the latest ``turtles``."""
    return [] if scene.turtles is None else turtles_but(scene.turtles, but=scene.turtle)


def follow(trail: collections.deque[tuple[float, float]], x: float, y: float) -> None:
    """Add (x, y) to ``trail`` if it is more than ``TRAIL_STEP`` m from the last position kept."""
    if not trail or math.hypot(trail[-1][0] - x, trail[-1][1] - y) > TRAIL_STEP:
        trail.append((x, y))


def goal_owner(key: str) -> str:
    """The turtle whose navigator publishes feedback on ``key``: turtle1 for
    ``navigate_to/feedback``, turtle2 for ``turtle2/navigate_to/feedback``."""
    return turtle_of(key.removesuffix(FEEDBACK).rstrip("/"))


def status_lines(scene: Scene) -> list[str]:
    """Two lines: where the turtle is and how fast; battery, goal and the keys."""
    if scene.router:
        where = f"no router at {scene.router}: reconnecting (is `turtlectl launch` running?)"
    elif scene.pose is None:
        where = f"waiting for {scene.turtle}/pose (is the sim running?)"
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


def run_view(
    session: zenoh.Session, world: World, endpoint: str = "", turtle: str = "", exit_on_loss: bool = False
) -> None:
    """Draw until q or Ctrl-C; the terminal is restored whatever happens.  ``turtle``: the
    followed turtle ("" turtle1; ``turtle2``: turtle2's pose, scan, status and goal, found in the
    namespace its nodes run in).
    RouterLost (Unreachable) when the router is lost and ``exit_on_loss``."""
    locale.setlocale(locale.LC_ALL, "")
    unicode = locale.getpreferredencoding(False).lower().replace("-", "") == "utf8"
    inbox: queue.SimpleQueue[tuple[float, str, bytes]] = queue.SimpleQueue()

    def take(sample: zenoh.Sample) -> None:  # Zenoh's thread: queue only
        inbox.put((time.monotonic(), str(sample.key_expr), sample.payload.to_bytes()))

    namespace = live_turtle_namespace(session, turtle or FIRST_TURTLE)  # turtle1's: "" or turtle1
    own = {key: resolve(key, namespace) for key in (POSE, STATUS, OBSTACLES, FEEDBACK)}
    keys = dict.fromkeys([own[POSE], own[STATUS], own[OBSTACLES], TURTLES, FEEDBACK, OTHERS_FEEDBACK])
    subs = [presence.subscriber(session, key, take) for key in keys]  # a namespace's feedback: */navigate_to/...
    scene = Scene(world=world, turtle=turtle_of(namespace))
    router = watch(session, endpoint or "the endpoint", "messages", exit_on_loss)
    trail: collections.deque[tuple[float, float]] = collections.deque(maxlen=TRAIL)
    trails: dict[str, collections.deque[tuple[float, float]]] = {}  # the other turtles', by name
    feedback_time = 0.0
    goal_times: dict[str, float] = {}  # when each other turtle's last feedback arrived

    def loop(screen: curses.window) -> None:
        nonlocal feedback_time
        curses.curs_set(0)
        screen.timeout(int(FRAME * 1000))
        next_world = time.monotonic() + WORLD_PERIOD
        while True:
            router.check(time.monotonic())
            scene.router = (endpoint or "the endpoint") if router.lost else ""
            if time.monotonic() >= next_world and not router.lost:
                next_world = time.monotonic() + WORLD_PERIOD
                session.get(WORLD_KEY, lambda r: r.ok is not None and take(r.ok), timeout=WORLD_PERIOD)
            while not inbox.empty():
                arrived, sample_key, payload = inbox.get_nowait()
                if sample_key == WORLD_KEY:  # the world, asked again: it may have appeared or changed
                    try:
                        scene.world = msgspec.json.decode(payload, type=World)
                    except msgspec.DecodeError:
                        pass
                    continue
                try:
                    msg = decode_any(payload)
                except ValueError:
                    continue
                if isinstance(msg, Pose) and sample_key == own[POSE]:
                    scene.pose = msg
                    follow(trail, msg.x, msg.y)
                elif isinstance(msg, TurtleStatus) and sample_key == own[STATUS]:
                    scene.status = msg
                elif isinstance(msg, LaserScan) and sample_key == own[OBSTACLES]:
                    scene.scan = msg
                elif isinstance(msg, NavigateToFeedback):
                    if (owner := goal_owner(sample_key)) == scene.turtle:
                        scene.feedback, feedback_time = msg, arrived
                    elif owner in trails:  # a turtle of this system's (not another domain's)
                        scene.goals[owner], goal_times[owner] = msg, arrived
                elif isinstance(msg, Turtles):
                    scene.turtles = msg
                    others_now = others(scene)
                    for gone in trails.keys() - {name for name, *_ in others_now}:  # killed
                        del trails[gone]
                    for name, x, y, _ in others_now:
                        follow(trails.setdefault(name, collections.deque(maxlen=TRAIL)), x, y)
            now = time.monotonic()
            if scene.feedback is not None and now - feedback_time > GOAL_LIFETIME:
                scene.feedback = None  # the goal ended
            for owner in [o for o in scene.goals if now - goal_times[o] > GOAL_LIFETIME or o not in trails]:
                del scene.goals[owner]
            scene.trail = list(trail)
            scene.trails = {name: list(points) for name, points in trails.items()}
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
                for points in trails.values():
                    points.clear()
            if key == curses.KEY_RESIZE:
                screen.clear()  # repaint the whole terminal on the next frame

    try:
        curses.wrapper(loop)
    except KeyboardInterrupt:
        pass
    finally:
        for sub in subs:
            sub.undeclare()
