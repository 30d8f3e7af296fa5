"""The pytest plugin of turtlectl (a ``pytest11`` entry point: active wherever turtlectl is
installed).  Fixtures:

* ``turtlectl_system``: a ``turtlectl.Client`` of a system started from your launch file for
  this test, every node ready; stopped after it.  Which launch file: the test's
  ``@pytest.mark.turtlectl_launch("path/launch.toml", "--set", "patrol.side=3")`` marker
  (path relative to the test file; the rest: ``launch`` options), else the ini option
  ``turtlectl_launch`` (relative to the rootdir), else ``launch.toml`` in the rootdir.
  ``pytest --turtlectl-time-scale 5`` (or the ini option ``turtlectl_time_scale``) starts it
  with ``launch --time-scale 5``: simulated time, five times as fast (a marker's own
  ``--time-scale`` wins).
* ``turtlectl_launch``: a factory, ``turtlectl_launch(path, *args) -> LaunchedSystem``, for
  a test that needs the system itself (its output, several systems); each is stopped after
  the test.

A node that dies while the system starts fails the test at once, with that node's output.
Nothing here is imported until a test uses a fixture.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

if TYPE_CHECKING:
    from turtlectl.cli.system.launched import LaunchedSystem
    from turtlectl.cli.tools.api import Client

MARKER = "turtlectl_launch"


TIME_SCALE = "turtlectl_time_scale"


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addini(MARKER, "the launch file turtlectl_system starts (relative to the rootdir)", default="launch.toml")
    parser.addini(
        TIME_SCALE, "turtlectl_system's systems run this many times as fast (launch --time-scale)", default=""
    )
    parser.getgroup("turtlectl").addoption(
        "--turtlectl-time-scale",
        dest=TIME_SCALE,
        metavar="F",
        default=None,
        help="turtlectl_system's systems run F times as fast, in simulated time (launch --time-scale F)",
    )


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers",
        f"{MARKER}(path, *options): the launch file turtlectl_system starts (relative to the test file) "
        "and more `turtlectl launch` options",
    )


@pytest.fixture
def turtlectl_launch(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Callable[..., LaunchedSystem]]:
    """A factory: ``turtlectl_launch(path, *launch_options, domain="") -> LaunchedSystem``, each
    system ready when returned and stopped after the test (its process group killed)."""
    from turtlectl.cli.errors import TurtlectlError
    from turtlectl.cli.system.launched import LaunchedSystem

    started: list[LaunchedSystem] = []

    def launch(path: str | Path, *args: str, domain: str = "") -> LaunchedSystem:
        system = LaunchedSystem(path, args, domain, tmp_path_factory.mktemp("turtlectl-logs"))
        started.append(system)
        try:
            return system.start()
        except TurtlectlError as exc:
            why = exc.message
        pytest.fail(why, pytrace=False)  # outside the except: one message, no chained traceback

    try:
        yield launch
    finally:
        for system in started:
            system.stop()


@pytest.fixture
def turtlectl_system(request: pytest.FixtureRequest, turtlectl_launch: Callable[..., Any]) -> Client:
    """A ``turtlectl.Client`` of the system your launch file starts for this test (the
    ``turtlectl_launch`` marker's file, else the ini option, else ``launch.toml`` in the rootdir)."""
    marker = request.node.get_closest_marker(MARKER)
    if marker is not None and marker.args:
        path, args = Path(request.path).parent / marker.args[0], [str(a) for a in marker.args[1:]]
    else:
        path, args = Path(request.config.rootpath) / request.config.getini(MARKER), []
    scale = request.config.getoption(TIME_SCALE) or request.config.getini(TIME_SCALE)
    if scale and "--time-scale" not in args:
        args = [*args, "--time-scale", str(scale)]
    return turtlectl_launch(path, *args).client()
