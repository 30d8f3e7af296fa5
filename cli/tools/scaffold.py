"""``turtlectl new node NAME``: a node class to start from, its unit test and what pytest needs,
in a project folder (as ``ros2 pkg create --node-name`` does).  Pure: returns the files to write
and refuses a name or a file that cannot be used; the command writes them."""

from __future__ import annotations

import keyword
import re
from pathlib import Path

from turtlectl.runtime.client.errors import BadInput

NODE = '''"""{camel}: drives forward while it knows where the turtle is. A start: make it yours."""

from __future__ import annotations

from typing import Annotated

import msgspec

from turtlectl import Interface, Node, run_main
from turtlectl.messages import Pose, Twist


class {camel}Params(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    # each field: its type and range (msgspec.Meta), its default, and `# unit: meaning`
    rate: Annotated[float, msgspec.Meta(gt=0.0, le=100.0)] = 10.0  # Hz: commands a second
    speed: Annotated[float, msgspec.Meta(ge=0.0, le=2.0)] = 0.5  # m/s: forward speed


class {camel}:
    Params = {camel}Params
    # what it publishes, subscribes to, serves, calls and watches: the runtime refuses anything else
    Interface = Interface(publishes=("turtle1/cmd_vel",), subscribes=("turtle1/pose",))

    def __init__(self, node: Node[{camel}Params]):
        self.node = node
        self.pose = node.latest("turtle1/pose", Pose)  # the newest pose, read at our own rate
        self.cmd = node.publisher("turtle1/cmd_vel", Twist)
        self.timer = node.timer(1.0 / node.params.rate, self.tick)
        node.on_params(lambda params: self.timer.retime(1.0 / params.rate))  # `param set {name} rate 5`
        node.on_shutdown(lambda: self.cmd.publish(Twist(linear=0.0, angular=0.0)))

    def tick(self) -> None:
        if self.pose.get() is not None:
            self.cmd.publish(Twist(linear=self.node.params.speed, angular=0.0))


if __name__ == "__main__":
    run_main({camel}, {camel}Params)
'''

TEST = '''"""{camel}, unit-tested without Zenoh: FakeNode runs it on a fake clock."""

from __future__ import annotations

from {name} import {camel}

from turtlectl.messages import Pose
from turtlectl.testing import FakeNode


def test_it_drives_once_it_knows_the_pose_and_stops_at_shutdown():
    with FakeNode({camel}, {{"rate": 10.0, "speed": 0.5}}) as fake:
        fake.advance(0.25)
        assert fake.published("turtle1/cmd_vel") == []  # no pose yet: no command
        fake.deliver("turtle1/pose", Pose(x=1.0, y=1.0, theta=0.0))
        fake.advance(0.1)
        assert [t.linear for t in fake.published("turtle1/cmd_vel")] == [0.5]
    assert fake.published("turtle1/cmd_vel")[-1].linear == 0.0  # the shutdown hook stopped it
'''

PYTEST_INI = """[pytest]
testpaths = tests
# the project folder on sys.path, so the tests import its node modules
pythonpath = .
"""

LAUNCH_ENTRY = """[[node]]
name = "{name}"
run = "./{name}.py:{camel}"
[node.params]
speed = 0.5                     # m/s
"""


def camel(name: str) -> str:
    return "".join(part.capitalize() for part in name.split("_"))


def node_files(name: str, folder: Path) -> dict[Path, str]:
    """The files ``new node NAME`` writes in ``folder``: ``NAME.py``, ``tests/test_NAME.py``, and
    ``pytest.ini`` where there is none.  BadInput for a name that is not a snake_case Python
    identifier, or a file that exists already (nothing is overwritten)."""
    if not re.fullmatch(r"[a-z][a-z0-9_]*", name) or keyword.iskeyword(name):
        raise BadInput(f"new node {name!r}: use a snake_case Python name (like patrol or wall_follower)")
    values = {"name": name, "camel": camel(name)}
    files = {folder / f"{name}.py": NODE.format(**values), folder / "tests" / f"test_{name}.py": TEST.format(**values)}
    taken = [str(path) for path in files if path.exists()]
    if taken:
        raise BadInput(f"new node {name}: {', '.join(taken)} exists already (nothing written)")
    if not (folder / "pytest.ini").exists():
        files[folder / "pytest.ini"] = PYTEST_INI
    return files


def launch_entry(name: str) -> str:
    """The launch file's ``[[node]]`` for it."""
    return LAUNCH_ENTRY.format(name=name, camel=camel(name))
