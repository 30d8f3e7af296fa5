"""runtime.loader: a launch file's ``run`` naming a user's node class, by module or by file,
and every way it can name none (one line each, saying why)."""

from __future__ import annotations

import sys
import textwrap
from pathlib import Path

import pytest

from turtlectl.runtime.loader import LoadError, absolute, is_target, load

PATROL = textwrap.dedent(
    """
    import msgspec


    class PatrolParams(msgspec.Struct, forbid_unknown_fields=True):
        side: float = 1.0


    class Patrol:
        Params = PatrolParams

        def __init__(self, node):
            self.node = node


    class NoParams:
        pass


    class BadParams:
        Params = dict


    patrol = 3
    """
)


@pytest.fixture
def project(tmp_path: Path) -> Path:
    (tmp_path / "patrol.py").write_text(PATROL)
    package = tmp_path / "uproj_pkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "patrol.py").write_text(PATROL)
    (package / "broken.py").write_text("import msgspec\n\ndef f(:\n    pass\n")
    (package / "missing.py").write_text("import msgspec\nimport no_such_module_here\n")
    (package / "raises.py").write_text("x = 1\nraise RuntimeError('boom at import')\n")
    return tmp_path


def test_a_target_has_a_colon_a_builtin_kind_has_none():
    assert is_target("./patrol.py:Patrol") and is_target("mypkg.patrol:Patrol") and not is_target("navigator")


def test_a_class_by_file_relative_to_the_base_folder(project):
    cls, params = load("./patrol.py:Patrol", project)
    assert cls.__name__ == "Patrol" and params.__name__ == "PatrolParams"
    assert absolute("./patrol.py:Patrol", project) == f"{project / 'patrol.py'}:Patrol"
    assert load(absolute("./patrol.py:Patrol", project))[0] is cls  # a file is imported once


def test_a_class_by_module_on_sys_path(project, monkeypatch):
    monkeypatch.syspath_prepend(str(project))
    cls, params = load("uproj_pkg.patrol:Patrol")
    assert cls.__module__ == "uproj_pkg.patrol" and params().side == 1.0
    assert absolute("uproj_pkg.patrol:Patrol", project) == "uproj_pkg.patrol:Patrol"


@pytest.mark.parametrize(
    ("target", "why"),
    [
        ("./nowhere.py:Patrol", "no file ./nowhere.py (looked for "),
        ("./patrol.py:Patrl", "patrol.py has no Patrl; did you mean Patrol? (its classes: PatrolParams, Patrol,"),
        ("./patrol.py:patrol", "patrol.py:patrol is not a class (a int)"),
        ("./patrol.py:NoParams", "patrol.py:NoParams is not a node class: it has no Params"),
        ("./patrol.py:BadParams", "patrol.py:BadParams.Params is not a msgspec.Struct class"),
        ("no_such_pkg_zz.patrol:Patrol", "cannot import no_such_pkg_zz.patrol: no module named 'no_such_pkg_zz'"),
        ("uproj_pkg.broken:X", "cannot import uproj_pkg.broken: SyntaxError: invalid syntax (broken.py, line 3)"),
        (
            "uproj_pkg.missing:X",
            "cannot import uproj_pkg.missing: ModuleNotFoundError: No module named 'no_such_module_here' "
            "(missing.py, line 2)",
        ),
        ("uproj_pkg.raises:X", "importing uproj_pkg.raises raised RuntimeError: boom at import (raises.py, line 2)"),
        ("patrol.py:", "'patrol.py:': write it as module:Class or ./file.py:Class"),
        ("my-pkg:Patrol", "'my-pkg' is not a module name"),
    ],
)
def test_a_target_that_names_no_node_class_says_why_in_one_line(project, monkeypatch, target, why):
    monkeypatch.syspath_prepend(str(project))
    with pytest.raises(LoadError) as caught:
        load(target, project)
    assert why in str(caught.value) and "\n" not in str(caught.value)


def test_a_files_siblings_come_first_as_for_python_file_py(tmp_path, monkeypatch):
    """A user's own ``messages.py`` (or ``nodes/``) beside the node file is what it imports, as
    ``python patrol.py`` would give it; ours are ``turtlectl.messages`` and never in the way
    (with the repository root on sys.path the node would get our messages package)."""
    monkeypatch.setattr("sys.path", list(sys.path))
    for name in ("messages", "nodes"):
        monkeypatch.delitem(sys.modules, name, raising=False)
    (tmp_path / "messages.py").write_text("import msgspec\n\nclass Waypoint(msgspec.Struct):\n    x: float\n")
    (tmp_path / "nodes").mkdir()
    (tmp_path / "nodes" / "__init__.py").write_text("LAPS = 3\n")
    (tmp_path / "walker.py").write_text(
        "import msgspec\nfrom messages import Waypoint\nfrom nodes import LAPS\n\n"
        "class Walker:\n    Params = msgspec.defstruct('WalkerParams', [('laps', int, LAPS)])\n"
        "    first = Waypoint(x=1.0)\n"
    )
    cls, params = load("./walker.py:Walker", tmp_path)
    assert cls.first.x == 1.0 and params().laps == 3
    import turtlectl.messages

    assert hasattr(turtlectl.messages, "Twist")
