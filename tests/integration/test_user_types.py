"""A user's own message type, defined in a project file and published by a user node,
is understood by the tools without a build step: the node describes it on the wire, `echo`
(block, --json, --field, --csv), `hz` (the publisher's rate), `interface list/show` and the
Python client use the description; a raw undescribed payload is shown generically; two nodes
describing one name differently are reported."""

from __future__ import annotations

import contextlib
import json
import textwrap
from collections.abc import Iterator

import msgspec
import pytest

import turtlectl
from tests.integration.harness import System, running_system

pytestmark = pytest.mark.integration

WALL = textwrap.dedent(
    '''
    import msgspec

    from turtlectl import Message


    class Corner(msgspec.Struct, frozen=True):
        x: float
        y: float


    class WallState(Message, tag="WallState"):
        """What the wall follower sees."""

        distance: float  # m: to the wall
        side: str = "left"  # -: which side the wall is on
        corners: list[Corner] = []  # m: corners seen
        stamp: int = 0  # ns: when it was published
        seq: int = 0  # -: per-publisher count


    class WallReset(Message, tag="WallReset"):
        """Start again from a distance."""

        to: float  # m: the distance to report


    class Wall:
        Params = msgspec.defstruct("WallParams", [])

        def __init__(self, node):
            pub = node.publisher("wall/state", WallState)
            node.timer(0.1, lambda: pub.publish(WallState(distance=0.75, corners=[Corner(1.0, 2.0)])))
            node.subscribe("wall/cmd", WallState, lambda m: node.log.info("heard distance %s", m.distance))
            node.serve("wall/restart", WallReset, WallState, lambda r: r.respond(WallState(distance=r.body.to)))


    '''
)

#: another version of wall.py (one package, wall): its WallState with other fields, as another
#: team's copy of the project would have (one module cannot hold two: launch --check refuses that)
OTHER_WALL = textwrap.dedent(
    '''
    import msgspec

    from turtlectl import Message


    class WallState(Message, tag="WallState"):
        """Another team's WallState: one name, another type."""

        level: int


    class Other:
        Params = msgspec.defstruct("OtherParams", [])

        def __init__(self, node):
            node.publisher("other/state", WallState)
    '''
)


@contextlib.contextmanager
def walls_system(tmp_path_factory) -> Iterator[System]:
    """The sim and the ``wall`` node (WALL's ``Wall``) from a project folder of their own."""
    project = tmp_path_factory.mktemp("walls")
    (project / "wall.py").write_text(WALL)
    (project / "launch.toml").write_text(
        '[[node]]\nname = "sim"\nrun = "sim"\n\n[[node]]\nname = "wall"\nrun = "./wall.py:Wall"\n'
    )
    with running_system(project / "launch.toml", ready=("sim", "wall"), cwd=project) as system:
        yield system


@pytest.fixture(scope="module")
def system(tmp_path_factory):
    with walls_system(tmp_path_factory) as system:
        yield system


def test_echo_shows_a_user_type_in_every_form(system):
    block = system.run_cli("echo", "wall/state", "--count", "2")
    assert block.returncode == 0, block.stderr
    assert block.stdout.count("# wall/WallState") == 2 and "distance: 0.75" in block.stdout, block.stdout
    assert "skipped" not in block.stderr, block.stderr
    line = json.loads(system.run_cli("echo", "wall/state", "--once", "--json").stdout)
    assert line["type"] == "wall/WallState" and line["corners"] == [{"x": 1.0, "y": 2.0}]
    assert system.run_cli("echo", "wall/state", "--once", "--field", "distance").stdout.strip() == "0.75"
    csv = system.run_cli("echo", "wall/state", "--count", "2", "--csv").stdout.splitlines()
    assert csv[0] == "distance,side,corners,stamp,seq" and csv[1].startswith("0.75,left,")


def test_hz_gives_the_publishers_own_rate(system):
    done = system.run_cli("hz", "wall/state", "--duration", "3")
    assert done.returncode == 0, done.stderr
    publisher = float(done.stdout.strip().splitlines()[-1].split("publisher ", 1)[1].split(" Hz")[0])
    assert 8.0 < publisher < 12.0, done.stdout


def test_interface_list_and_show_a_live_user_type(system):
    listed = system.run_cli("interface", "list")
    assert "wall/WallState" in listed.stdout and "(used by wall)" in listed.stdout, listed.stdout
    shown = system.run_cli("interface", "show", "WallState")
    assert shown.returncode == 0, shown.stderr
    assert "described by: wall (hash TH01_" in shown.stdout and "to the wall" in shown.stdout, shown.stdout
    # keys from the live graph, Python-like types, required
    keys = next(line for line in shown.stdout.splitlines() if line.startswith("keys: "))
    assert "wall/state" in keys and "none of its own" not in keys, shown.stdout
    distance = next(line for line in shown.stdout.splitlines() if line.startswith("distance "))
    assert distance.split()[:4] == ["distance", "float", "required", "m"], shown.stdout
    assert "list[Corner]" in shown.stdout, shown.stdout
    nested = system.run_cli("interface", "show", "Corner")  # a Struct nested in a live type
    assert nested.returncode == 0, nested.stderr
    assert nested.stdout.startswith("Corner: a map nested in wall/WallState") and "\nx " in nested.stdout, nested.stdout
    unknown = system.run_cli("interface", "show", "Nope")
    assert unknown.returncode == 2 and "Twist" in unknown.stderr and "WallState" in unknown.stderr, unknown.stderr


def test_the_python_client_decodes_a_user_type_with_attribute_access(system):
    with turtlectl.Client(system.endpoint) as client:
        state = client.latest("wall/state")
        assert type(state).__name__ == "WallState" and state.distance == 0.75 and state.corners[0].y == 2.0


def test_an_undescribed_payload_is_shown_as_what_it_is(system):
    session = system.session
    assert session is not None
    sub = system.run_cli  # noqa: F841  (the echo below runs while we publish)
    import subprocess

    from tests.integration.harness import turtlectl as command

    echo = subprocess.Popen(
        [*command(), "echo", "raw/data", "--once", "--connect", system.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        system.wait_until(lambda: echo.poll() is not None or _put(session), 20.0, "echo got it")
        out, err = echo.communicate(timeout=20)
    finally:
        if echo.poll() is None:
            echo.kill()
    assert "# Mystery (undescribed)" in out and "a: 1" in out, (out, err)
    assert "skipped" not in err


def _put(session) -> bool:
    session.put("raw/data", msgspec.msgpack.encode({"type": "Mystery", "a": 1}), encoding="application/msgpack;Mystery")
    return False


def test_two_descriptions_of_one_name_are_reported(system, tmp_path):
    import subprocess

    from tests.integration.harness import turtlectl as command

    (tmp_path / "wall.py").write_text(OTHER_WALL)
    other = subprocess.Popen(
        [*command(), "run", "./wall.py:Other", "--connect", system.endpoint],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        system.wait_until(lambda: "other" in system.alive or other.poll() is not None, 30.0, "the other node")
        shown = system.run_cli("interface", "show", "WallState")
        assert "CONFLICT: described 2 ways:" in shown.stdout and " by other" in shown.stdout, shown.stdout
        listed = system.run_cli("interface", "list")
        assert "CONFLICT" in listed.stdout
        graph = system.run_cli("list")
        assert "CONFLICTS" in graph.stdout and "wall/WallState is described 2 ways:" in graph.stdout, graph.stdout
        echoed = system.run_cli("echo", "wall/state", "--once")  # met by echo too
        assert "warning: wall/WallState is described 2 ways:" in echoed.stderr, echoed.stderr
    finally:
        other.terminate()
        other.wait(10)


def test_pub_and_call_build_a_user_type_from_json_validated(system):
    sent = system.run_cli("pub", "wall/cmd", '{"distance": 2.5}')  # its type: from the graph and the node
    assert sent.returncode == 0, sent.stderr
    system.wait_line(r"heard distance 2.5", 20.0)
    bad = system.run_cli("pub", "wall/cmd", '{"distance": "far"}')
    assert bad.returncode == 2 and "not a valid wall/WallState: distance: Expected `float`, got `str`" in bad.stderr, (
        bad
    )
    answered = system.run_cli("call", "wall/restart", '{"to": 1.5}')
    assert answered.returncode == 0, answered.stderr
    assert "# wall/WallState" in answered.stdout and "distance: 1.5" in answered.stdout, answered.stdout
