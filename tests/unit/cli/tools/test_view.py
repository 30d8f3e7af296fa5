"""cli.tools.view: the picture drawn from the latest messages (no terminal needed)."""

import math

from turtlectl.cli.tools.view import Scene, render
from turtlectl.messages import (
    LaserScan,
    NavigateToFeedback,
    Pose,
    TurtleStatus,
)
from turtlectl.messages.world import Obstacle, World


def test_view_draws_walls_obstacles_turtle_goal_and_status():
    world = World(size=10.0, obstacles=[Obstacle(x=8.0, y=8.0, radius=1.0)])
    scene = Scene(
        world=world,
        pose=Pose(x=5.0, y=5.0, theta=math.pi / 2),
        status=TurtleStatus(x=5, y=5, theta=90, vel_x=0, vel_y=0, battery=77.0),
        feedback=NavigateToFeedback(
            state="driving",
            distance_remaining=2,
            heading_remaining=0,
            eta=1,
            elapsed=0,
            x=5,
            y=5,
            theta=90,
            goal_x=2,
            goal_y=2,
        ),
        trail=[(4.0, 4.0)],
    )
    lines = render(scene, 60, 24)
    assert len(lines) == 24 and all(len(line) <= 60 for line in lines)
    assert lines[0].startswith("+-") and lines[0].endswith("+")
    grid = "\n".join(lines[1:-3])
    assert "↑" in grid and "X" in grid and "o" in grid and "." in grid
    assert "x  5.00 y  5.00 heading  90.0 deg" in lines[-2]
    assert "battery 77.0 %" in lines[-1] and "goal (2.00, 2.00) driving" in lines[-1] and "q quits" in lines[-1]
    assert "^" in "\n".join(render(scene, 60, 24, unicode=False))
    assert render(scene, 10, 3) == ["terminal too small"]


def test_the_view_has_a_legend_scan_hits_and_says_when_the_router_is_lost():
    scan = LaserScan(  # one beam straight ahead of a turtle facing +y: the hit is above it
        angle_min=0.0,
        angle_max=0.0,
        angle_increment=0.0,
        range_min=0.0,
        range_max=10.0,
        ranges=[3.0],
        origin_x=5.0,
        origin_y=2.0,
        origin_theta=math.pi / 2,
    )
    scene = Scene(world=World(size=10.0), pose=Pose(x=5.0, y=2.0, theta=math.pi / 2), scan=scan)
    lines = render(scene, 60, 24)
    grid = lines[1:-4]
    (hit_row,) = [i for i, row in enumerate(grid) if "*" in row]
    (turtle_row,) = [i for i, row in enumerate(grid) if "↑" in row]
    assert hit_row < turtle_row and grid[hit_row].index("*") == grid[turtle_row].index("↑")
    wide = render(scene, 80, 24)
    assert any(
        "o obstacle" in line and "* scan hit" in line and ". trail" in line and "+ path" in line and "X goal" in line
        for line in wide
    )
    assert any("c clears the trail" in line for line in wide)
    scene.router = "tcp/127.0.0.1:7447"
    assert "no router at tcp/127.0.0.1:7447" in render(scene, 80, 24)[-2]
    status = TurtleStatus(x=5, y=5, theta=0, vel_x=0, vel_y=0, battery=50)
    heading = render(Scene(world=World(size=10.0), pose=Pose(x=5.0, y=5.0, theta=-1e-9), status=status), 80, 24)[-2]
    assert "heading   0.0 deg" in heading


def test_the_view_draws_the_goals_path_round_an_obstacle():
    world = World(size=10.0, obstacles=[Obstacle(x=5.0, y=5.0, radius=1.0)])
    path = [(2.0, 5.0), (4.0, 6.6), (5.0, 6.9), (6.0, 6.6), (8.0, 5.0)]  # over the top of it
    fb = NavigateToFeedback(
        state="driving", distance_remaining=7, heading_remaining=0, eta=2, elapsed=0, x=2, y=5, theta=0,
        goal_x=8, goal_y=5, path=path,
    )  # fmt: skip
    lines = render(Scene(world=world, pose=Pose(x=2.0, y=5.0, theta=0.0), feedback=fb), 60, 24)
    grid = lines[1:-4]
    rows_with_path = [i for i, row in enumerate(grid) if "+" in row.strip("|")]
    obstacle_rows = [i for i, row in enumerate(grid) if "o" in row]
    assert rows_with_path and min(rows_with_path) < min(obstacle_rows)  # it goes above the obstacle
    assert any("+ path" in line for line in lines)
    plain = render(Scene(world=world, pose=Pose(x=2.0, y=5.0, theta=0.0)), 60, 24)[1:-4]
    assert not any("+" in row.strip("|") for row in plain)


def test_the_view_draws_every_turtle_and_names_the_others():
    """Spawned turtles are drawn as turtle1 is (an arrow along the heading) and named
    beside the legend with where they are."""
    from turtlectl.messages import Turtles

    scene = Scene(
        world=World(size=10.0),
        pose=Pose(x=5.0, y=5.0, theta=0.0),
        turtles=Turtles(
            names=["turtle1", "turtle2", "alice"],
            x=[5.0, 2.0, 8.0],
            y=[5.0, 2.0, 8.0],
            theta=[0.0, math.pi / 2, math.pi],
        ),
    )
    lines = render(scene, 120, 30)
    grid = "\n".join(lines[1:-3])
    assert grid.count("→") == 1 and grid.count("↑") == 1 and grid.count("←") == 1
    assert lines[-3].endswith("| also: turtle2 (2.0, 2.0), alice (8.0, 8.0)"), lines[-3]
    # the legend is cut at the terminal's width, so each is also named on the map
    assert next(line for line in lines if "↑turtle2" in line) and next(line for line in lines if "←alice" in line)
    assert any("↑turtle2" in line for line in render(scene, 80, 24))
    alone = render(Scene(world=World(size=10.0), pose=Pose(x=5.0, y=5.0, theta=0.0)), 120, 30)
    assert "also:" not in alone[-3] and "\n".join(alone[1:-3]).count("→") == 1


def test_the_view_draws_the_other_turtles_trails_and_goals():
    """Each other turtle's trail (as turtle1's) and its running goal (path and X), the
    goal also said beside its name; a turtle without feedback has no goal drawn."""
    from turtlectl.messages import Turtles

    fb = NavigateToFeedback(
        state="driving", distance_remaining=6, heading_remaining=0, eta=2, elapsed=0, x=2, y=2, theta=0,
        goal_x=8, goal_y=2, path=[(2.0, 2.0), (8.0, 2.0)],
    )  # fmt: skip
    turtles = Turtles(names=["turtle1", "turtle2", "turtle3"], x=[5.0, 2.0, 8.0], y=[8.0, 2.0, 8.0], theta=[0.0] * 3)
    scene = Scene(
        world=World(size=10.0),
        pose=Pose(x=5.0, y=8.0, theta=0.0),
        turtles=turtles,
        trails={"turtle3": [(8.0, y / 2) for y in range(6, 15)]},  # a column below turtle3
        goals={"turtle2": fb},
    )
    lines = render(scene, 150, 30)
    grid = lines[1:-4]
    assert "\n".join(grid).count("X") == 1 and "\n".join(grid).count("+") >= 5  # turtle2's goal and path
    (goal_row,) = [row for row in grid if "X" in row]
    assert "+" in goal_row and goal_row.index("+") < goal_row.index("X")  # the path runs from turtle2 to it
    (arrow_row,) = [i for i, row in enumerate(grid) if row.count("→") == 2]  # turtle1 and turtle3
    column = grid[arrow_row].rindex("→")
    assert sum(row[column] == "." for row in grid[arrow_row + 1 :]) >= 3  # turtle3's trail below it
    assert lines[-3].endswith("| also: turtle2 (2.0, 2.0) goal (8.0, 2.0), turtle3 (8.0, 8.0)"), lines[-3]
    assert "no goal" in lines[-1]  # turtle1's own status line is unchanged: it has none


def test_the_view_tells_whose_feedback_a_key_is_and_keeps_a_trail_a_step_apart():
    import collections

    from turtlectl.cli.tools.view import follow, goal_owner

    assert goal_owner("navigate_to/feedback") == "turtle1"
    assert goal_owner("turtle2/navigate_to/feedback") == "turtle2"
    trail = collections.deque(maxlen=3)
    for x in (0.0, 0.01, 0.1, 0.2, 0.3):
        follow(trail, x, 0.0)
    assert list(trail) == [(0.1, 0.0), (0.2, 0.0), (0.3, 0.0)]


def test_labels_are_drawn_whole_never_over_one_another_nor_run_together():
    from turtlectl.cli.tools.view import place_label

    def row(text: str) -> list[list[str]]:
        return [list(text)]

    grid = row("     →              ↑         ")
    assert place_label(grid, 0, 5, "turtle2") and place_label(grid, 0, 20, "turtle3")
    assert "".join(grid[0]) == "     →turtle2       ↑turtle3  "
    crowded = row("     →       ↑      ")  # turtle2's name would run into the next arrow: left out
    assert not place_label(crowded, 0, 5, "turtle2") and "".join(crowded[0]) == "     →       ↑      "
    edge = row("                  ← ")  # no room on the right: on the left
    assert place_label(edge, 0, 18, "ab") and "".join(edge[0]) == "                ab← "
    near = row("  →ab ← o")  # a label already there, an obstacle: neither side is open
    assert not place_label(near, 0, 6, "cd")


def test_the_view_follows_the_turtle_given_and_names_turtle1_among_the_others():
    from turtlectl.messages import Turtles

    scene = Scene(
        world=World(size=10.0),
        turtle="turtle2",
        pose=Pose(x=2.0, y=2.0, theta=0.0),
        turtles=Turtles(names=["turtle1", "turtle2"], x=[8.0, 2.0], y=[8.0, 2.0], theta=[0.0, 0.0]),
    )
    lines = render(scene, 120, 30)
    assert lines[-3].endswith("| also: turtle1 (8.0, 8.0)"), lines[-3]
    assert any("→turtle1" in line for line in lines)
    waiting = render(Scene(world=World(size=10.0), turtle="turtle2"), 120, 30)
    assert "waiting for turtle2/pose" in waiting[-2]
