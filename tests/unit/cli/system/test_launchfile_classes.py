"""cli.system.launchfile with a user's node class as ``run``: its parameters are
validated by ``launch --check`` exactly as a built-in kind's (file, key path, nearest key), a
``run`` that names no node class is one line, and only kinds that claim something are one
per system."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from turtlectl.cli.system.launchfile import LaunchFileError, load_launch
from turtlectl.cli.system.overrides import class_plan, node_config, parse_assignment, with_overrides

PATROL = textwrap.dedent(
    """
    from typing import Annotated

    import msgspec

    from turtlectl.runtime.config import Claim


    class Gains(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
        turn: float = 1.5


    class PatrolParams(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
        side: Annotated[float, msgspec.Meta(gt=0.0, le=10.0)] = 2.0  # m: the square's side
        gains: Gains = msgspec.field(default_factory=Gains)


    class Patrol:
        Params = PatrolParams

        def __init__(self, node):
            pass


    class Poser:
        Params = PatrolParams
        Claims = (Claim("pub", "turtle1/pose"),)
    """
)


def launch(tmp_path: Path, body: str) -> Path:
    (tmp_path / "patrol.py").write_text(PATROL)
    path = tmp_path / "launch.toml"
    path.write_text(textwrap.dedent(body))
    return path


SIM = '[[node]]\nname = "sim"\nrun = "sim"\n'


def test_a_node_class_by_file_runs_beside_the_builtins_with_its_params_validated(tmp_path):
    path = launch(
        tmp_path,
        SIM + '[[node]]\nname = "patrol"\nrun = "./patrol.py:Patrol"\nparams = { side = 3.0 }\n'
        '[[node]]\nname = "patrol2"\nrun = "./patrol.py:Patrol"\n',
    )
    plan = load_launch(path)
    assert plan.params["patrol"] == {"side": 3.0, "gains": {"turn": 1.5}}
    kind = plan.kinds["patrol"]
    assert kind.target == f"{tmp_path / 'patrol.py'}:Patrol" and not kind.builtin and not kind.claims
    assert plan.kinds["patrol2"] == kind  # claims nothing: as many as wanted
    config = node_config(plan, "patrol", "tcp/127.0.0.1:7447")
    assert config.kind == "./patrol.py:Patrol" and config.params["side"] == 3.0 and config.claims == []


@pytest.mark.parametrize(
    ("params", "error"),
    [
        ("{ sidee = 3.0 }", "node[1] (patrol).params.sidee: unknown key; did you mean side?"),
        ("{ side = -1.0 }", "node[1] (patrol).params.side must be > 0"),
        ("{ gains = { trun = 1.0 } }", "node[1] (patrol).params.gains.trun: unknown key; did you mean turn?"),
    ],
)
def test_a_node_class_s_params_are_checked_as_a_builtin_s(tmp_path, params, error):
    path = launch(tmp_path, SIM + f'[[node]]\nname = "patrol"\nrun = "./patrol.py:Patrol"\nparams = {params}\n')
    with pytest.raises(LaunchFileError) as caught:
        load_launch(path)
    assert str(caught.value).startswith(f"{path}: {error}")


def test_an_override_of_a_node_class_s_params_is_checked_too(tmp_path):
    plan = load_launch(launch(tmp_path, SIM + '[[node]]\nname = "patrol"\nrun = "./patrol.py:Patrol"\n'))
    with pytest.raises(LaunchFileError, match=r"^--set patrol.sid: unknown key; did you mean side\?$"):
        with_overrides(plan, [parse_assignment("patrol.sid=1", "--set", "")], "--set")


@pytest.mark.parametrize(
    ("run", "error"),
    [
        ("./nope.py:Patrol", "node[1] (patrol).run: no file ./nope.py (looked for "),
        ("./patrol.py:Patrl", "node[1] (patrol).run: patrol.py has no Patrl; did you mean Patrol?"),
        ("./patrol.py:Gains", "node[1] (patrol).run: patrol.py:Gains is not a node class: it has no Params"),
        ("no_such_pkg_zz.patrol:Patrol", "node[1] (patrol).run: cannot import no_such_pkg_zz.patrol: no module"),
        (
            "patrl",
            "node[1] (patrol).run: unknown node kind 'patrl' (known: navigator, obstacle_detector, ros2_bridge, sim, ",
        ),
    ],
)
def test_a_run_that_names_no_node_class_is_one_line(tmp_path, run, error):
    path = launch(tmp_path, SIM + f'[[node]]\nname = "patrol"\nrun = "{run}"\n')
    with pytest.raises(LaunchFileError) as caught:
        load_launch(path)
    assert str(caught.value).startswith(f"{path}: {error}") and "\n" not in str(caught.value)


def test_a_class_that_claims_what_a_builtin_claims_clashes_with_it(tmp_path):
    path = launch(tmp_path, SIM + '[[node]]\nname = "poser"\nrun = "./patrol.py:Poser"\n')
    with pytest.raises(LaunchFileError, match=r"node\[1\] \(poser\).run: node\[0\] \(sim\) already claims"):
        load_launch(path)


def test_run_takes_a_node_class_with_its_defaults_and_overrides(tmp_path):
    (tmp_path / "patrol.py").write_text(PATROL)
    plan, name = class_plan("./patrol.py:Patrol", ["side=4", "gains.turn=2"], tmp_path)
    assert name == "patrol" and plan.params[name] == {"side": 4, "gains": {"turn": 2}}
    with pytest.raises(LaunchFileError, match=r"^--param patrol.sid: unknown key; did you mean side\?$"):
        class_plan("./patrol.py:Patrol", ["sid=4"], tmp_path)
    with pytest.raises(LaunchFileError, match=r"^./patrol.py:Patrl: patrol.py has no Patrl"):
        class_plan("./patrol.py:Patrl", [], tmp_path)


def test_run_puts_a_node_class_in_a_namespace(tmp_path):
    """`turtlectl run ./patrol.py:Patrol --namespace turtle2` is turtle2/patrol, its keys turtle2's."""
    from turtlectl.cli.system.overrides import node_config

    (tmp_path / "patrol.py").write_text(PATROL)
    plan, name = class_plan("./patrol.py:Patrol", ["side=4"], tmp_path, namespace="turtle2")
    assert name == "turtle2/patrol" and plan.params[name]["side"] == 4
    config = node_config(plan, name, "tcp/127.0.0.1:1")
    assert config.name == "turtle2/patrol"
    with pytest.raises(LaunchFileError, match="is not a namespace"):
        class_plan("./patrol.py:Patrol", [], tmp_path, namespace="a b")


def project(folder: Path, package: str, imports: str) -> Path:
    """A student's project: ``package`` with two modules each declaring its own ``TurtleStatus``,
    and a node class whose module runs ``imports``; its launch file."""
    (folder / package).mkdir()
    (folder / package / "__init__.py").write_text("")
    status = "from turtlectl import Message\n\nclass TurtleStatus(Message, tag='TurtleStatus'):\n    x: float = 0.0\n"
    (folder / package / "status.py").write_text(status)
    (folder / package / "more.py").write_text(status.replace("x: float", "mood: str"))
    node = (
        "import msgspec\n"
        + imports
        + "\n\nclass Monitor:\n    Params = msgspec.Struct\n\n    def __init__(self, node):\n        pass\n"
    )
    (folder / "monitor.py").write_text(node)
    (folder / "launch.toml").write_text(SIM + '[[node]]\nname = "monitor"\nrun = "./monitor.py:Monitor"\n')
    return folder / "launch.toml"


@pytest.fixture
def projects(tmp_path, monkeypatch):
    """Where the projects go, on sys.path (as the loader finds a project's own modules)."""
    import sys

    monkeypatch.setattr(sys, "modules", dict(sys.modules))  # the projects' modules go with the test
    for name in ("ok", "clash"):
        (tmp_path / name).mkdir()
        monkeypatch.syspath_prepend(str(tmp_path / name))
    return tmp_path


def test_two_classes_under_one_type_name_are_found_by_the_check_not_by_a_crash_loop(projects):
    """Two modules of one package each declaring its own ``TurtleStatus`` are both
    ``capstone_msgs/TurtleStatus``: a node using both could never start.  A user's TurtleStatus
    beside turtlectl's is no clash (another package)."""
    fine = project(
        projects / "ok",
        "ok_msgs",
        "from ok_msgs.status import TurtleStatus\nfrom turtlectl.messages import TurtleStatus as Theirs",
    )
    assert load_launch(fine).kinds["monitor"]
    clash = project(projects / "clash", "capstone_msgs", "import capstone_msgs.more\nimport capstone_msgs.status")
    with pytest.raises(LaunchFileError) as err:
        load_launch(clash)
    message = str(err.value)
    assert "node[1] (monitor).run: two message types named 'capstone_msgs/TurtleStatus'" in message, message
    assert "capstone_msgs.more.TurtleStatus and capstone_msgs.status.TurtleStatus" in message
