"""The pytest plugin of turtlectl (a ``pytest11`` entry point: active wherever turtlectl is
installed).  Fixtures:

* ``turtlectl_system``: a ``turtlectl.Client`` of a system started from your launch file,
  every node ready.  Which launch file: the closest ``turtlectl_launch`` marker, on the test,
  its class or its module (``pytestmark``):
  ``@pytest.mark.turtlectl_launch("path/launch.toml", "--set", "patrol.side=3")`` (path
  relative to the test file; the rest: ``launch`` options), else the ini option
  ``turtlectl_launch`` (relative to the rootdir), else ``launch.toml`` in the rootdir.
  ``pytest --turtlectl-time-scale 5`` (or the ini option ``turtlectl_time_scale``) starts it
  with ``launch --time-scale 5``: simulated time, five times as fast (a marker's own
  ``--time-scale`` wins).
* Shared systems: ``pytest --turtlectl-scope module`` (or the ini option ``turtlectl_scope``;
  ``function``, the default, ``class``, ``module``, ``package`` or ``session``) keeps each
  system for every test of that scope asking for the same launch file and options: it
  starts with the first, stops after the last.  Each test gets a Client of its own.  A
  marker's ``fresh=True`` gives its tests a system of their own whatever the scope.
* ``turtlectl_launch``: a factory, ``turtlectl_launch(path, *args) -> LaunchedSystem``, for
  a test that needs the system itself (its output, several systems); each is stopped after
  the test.

A node that dies while the system starts fails the test at once, with that node's output;
one that exits with an error once the system runs fails the test it happened in (or, between
tests, the next one using that system), with its output too.  Nothing here is imported until
a test uses a fixture.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import pytest

if TYPE_CHECKING:
    from turtlectl.cli.system.launched import LaunchedSystem
    from turtlectl.runtime.client.api import Client

MARKER = "turtlectl_launch"
TIME_SCALE = "turtlectl_time_scale"
SCOPE = "turtlectl_scope"
SCOPES = ("function", "class", "module", "package", "session")


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addini(MARKER, "the launch file turtlectl_system starts (relative to the rootdir)", default="launch.toml")
    parser.addini(
        TIME_SCALE, "turtlectl_system's systems run this many times as fast (launch --time-scale)", default=""
    )
    parser.addini(SCOPE, f"how long a turtlectl_system system is shared: {', '.join(SCOPES)}", default="function")
    group = parser.getgroup("turtlectl")
    group.addoption(
        "--turtlectl-time-scale",
        dest=TIME_SCALE,
        metavar="F",
        default=None,
        help="turtlectl_system's systems run F times as fast, in simulated time (launch --time-scale F)",
    )
    group.addoption(
        "--turtlectl-scope",
        dest=SCOPE,
        metavar="SCOPE",
        default=None,
        help=f"share each turtlectl_system system for a whole SCOPE: {', '.join(SCOPES)} (default: function)",
    )


def _scope_of(config: pytest.Config) -> str:
    return str(config.getoption(SCOPE) or config.getini(SCOPE) or "function").strip()


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers",
        f"{MARKER}(path, *options, fresh=False): the launch file turtlectl_system starts (relative to the test "
        "file) and more `turtlectl launch` options; fresh=True: a system of the test's own, never shared",
    )
    scope = _scope_of(config)
    if scope not in SCOPES:
        raise pytest.UsageError(f"turtlectl_scope must be one of {', '.join(SCOPES)} (got {scope!r})")


def _systems_scope(fixture_name: str, config: pytest.Config) -> str:
    return _scope_of(config)


def _started(system: LaunchedSystem) -> LaunchedSystem:
    """``system`` started; a start that fails fails the test with one message."""
    from turtlectl.runtime.client.errors import TurtlectlError

    try:
        return system.start()
    except TurtlectlError as exc:
        why = exc.message
    pytest.fail(why, pytrace=False)  # outside the except: one message, no chained traceback


class _Shared:
    """The systems of one scope, one per launch file and options: each started by the first
    test asking for it (a start that failed fails the others at once, without starting it
    again), all stopped when the scope ends.  ``reported``: how many of a system's node exits
    a test has been failed with."""

    def __init__(self, scope: str, tmp_path_factory: pytest.TempPathFactory):
        self.scope = scope
        self._tmp = tmp_path_factory
        self._systems: dict[tuple[Path, tuple[str, ...]], LaunchedSystem] = {}
        self._failed: dict[tuple[Path, tuple[str, ...]], str] = {}
        self.reported: dict[int, int] = {}

    def get(self, path: Path, args: list[str]) -> LaunchedSystem:
        from turtlectl.cli.system.launched import LaunchedSystem
        from turtlectl.runtime.client.errors import TurtlectlError

        key = (path.resolve(), tuple(args))
        if key in self._failed:
            pytest.fail(f"(the {self.scope}'s shared system did not start) {self._failed[key]}", pytrace=False)
        if key not in self._systems:
            system = LaunchedSystem(path, args, "", self._tmp.mktemp("turtlectl-logs"))
            self._systems[key] = system
            try:
                system.start()
            except TurtlectlError as exc:
                self._failed[key] = exc.message
                why = exc.message
            else:
                return system
            pytest.fail(why, pytrace=False)
        return self._systems[key]

    def check(self, system: LaunchedSystem, when: str) -> None:
        """Fail the test if a node of ``system`` exited with an error since the last check, or
        the launch itself ended (each exit reported once: a respawned node serves on)."""
        why = self._news(system, when)
        if why:
            pytest.fail(why, pytrace=False)

    def _news(self, system: LaunchedSystem, when: str) -> str:
        seen = self.reported.get(id(system), 0)
        new = [e for e in system.exits[seen:] if e.code != 0]
        self.reported[id(system)] = len(system.exits)
        if new:
            return "\n\n".join(f"{e} {when}:\n{system.output_of(e.node)}" for e in new)
        if not system.running():
            return f"turtlectl launch ended {when}:\n{system.output()}"
        return ""

    def close(self) -> None:
        """Stop every system; an exit not reported yet (after the last test) fails the scope."""
        news = [self._news(system, "after the last test using it") for system in self._systems.values()]
        for system in self._systems.values():
            system.stop()
        self._systems.clear()
        if any(news):
            pytest.fail("\n\n".join(n for n in news if n), pytrace=False)


@pytest.fixture(scope=_systems_scope)
def _turtlectl_shared(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Iterator[_Shared]:
    """The systems turtlectl_system shares for the scope chosen (``turtlectl_scope``)."""
    shared = _Shared(request.scope, tmp_path_factory)
    try:
        yield shared
    finally:
        shared.close()


@pytest.fixture
def turtlectl_launch(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Callable[..., LaunchedSystem]]:
    """A factory: ``turtlectl_launch(path, *launch_options, domain="") -> LaunchedSystem``, each
    system ready when returned and stopped after the test (its process group killed)."""
    from turtlectl.cli.system.launched import LaunchedSystem

    started: list[LaunchedSystem] = []

    def launch(path: str | Path, *args: str, domain: str = "") -> LaunchedSystem:
        system = LaunchedSystem(path, args, domain, tmp_path_factory.mktemp("turtlectl-logs"))
        started.append(system)
        return _started(system)

    try:
        yield launch
    finally:
        for system in started:
            system.stop()


@pytest.fixture
def turtlectl_system(
    request: pytest.FixtureRequest, _turtlectl_shared: _Shared, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[Client]:
    """A ``turtlectl.Client`` of the system your launch file starts (the closest
    ``turtlectl_launch`` marker's file, else the ini option, else ``launch.toml`` in the
    rootdir), shared for the ``turtlectl_scope`` chosen (default: this test's own)."""
    marker = request.node.get_closest_marker(MARKER)
    if marker is not None and marker.args:
        path, args = Path(request.path).parent / marker.args[0], [str(a) for a in marker.args[1:]]
    else:
        path, args = Path(request.config.rootpath) / request.config.getini(MARKER), []
    scale = request.config.getoption(TIME_SCALE) or request.config.getini(TIME_SCALE)
    if scale and "--time-scale" not in args:
        args = [*args, "--time-scale", str(scale)]
    fresh = marker is not None and bool(marker.kwargs.get("fresh", False))
    shared = _Shared("function", tmp_path_factory) if fresh else _turtlectl_shared
    try:
        system = shared.get(path, args)
        where = "between the tests sharing this system" if shared.scope != "function" else "before this test"
        shared.check(system, f"{where} (it runs for the {shared.scope})")
        client = system.client()
        yield client
        client.close()
        shared.check(system, f"during {request.node.name}")
    finally:
        if fresh:
            shared.close()
