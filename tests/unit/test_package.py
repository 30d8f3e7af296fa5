"""One package.  The wheel installs ``turtlectl`` and nothing else at the top of
site-packages, typed (``py.typed``), with the launch file and Foxglove layout it reads; the
installed package is the source tree's folders mapped under it, and its public names load
lazily; in the source tree (the editable install) ``import messages`` finds nothing of ours."""

from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import turtlectl

ROOT = Path(__file__).resolve().parents[2]
#: what the wheel is built from (pyproject.toml's package-dir), copied so the build writes nothing here
SOURCES = ("pyproject.toml", "README.md", "launch.toml", "src", "messages", "runtime", "sim", "nodes", "cli")


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    source = tmp_path_factory.mktemp("source")
    for name in SOURCES:
        path = ROOT / name
        ignore = shutil.ignore_patterns("__pycache__")
        shutil.copytree(path, source / name, ignore=ignore) if path.is_dir() else shutil.copy(path, source)
    out = tmp_path_factory.mktemp("wheel")
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--quiet",
            "--no-deps",
            "--disable-pip-version-check",
            "-w",
            out,
            source,
        ],
        check=True,
        capture_output=True,
        timeout=600,
    )
    (built,) = out.glob("turtlectl-*.whl")
    return built


def test_the_wheel_holds_turtlectl_and_nothing_else(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    assert {n.split("/")[0] for n in names} == {"turtlectl", wheel.name.split("-py3")[0] + ".dist-info"}
    for data in ("py.typed", "cli/system/launch.toml", "cli/foxglove/foxglove_layout.json", "messages/types.py"):
        assert f"turtlectl/{data}" in names


def test_the_installed_package_is_complete_without_the_source_tree(wheel, tmp_path):
    with zipfile.ZipFile(wheel) as z:
        z.extractall(tmp_path / "site")
    code = (
        "import sys, turtlectl, turtlectl.cli.main, turtlectl.messages\n"
        "from turtlectl.cli.system.launchfile import PACKAGED_LAUNCH\n"
        "print(turtlectl.__path__, turtlectl.messages.__file__, PACKAGED_LAUNCH.is_file())\n"
        "print(turtlectl.Node.__module__, turtlectl.Message.__name__, turtlectl.Interface.__name__)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={"PYTHONPATH": str(tmp_path / "site"), "PATH": "/usr/bin:/bin"},
        check=False,
    )
    assert done.returncode == 0, done.stderr
    site = tmp_path / "site" / "turtlectl"
    assert done.stdout.splitlines() == [
        f"[{str(site)!r}] {site / 'messages' / '__init__.py'} True",
        "turtlectl.runtime.node Message Interface",
    ]


def test_the_public_names_are_documented_typed_and_lazy():
    assert (ROOT / "src" / "turtlectl" / "py.typed").is_file()
    code = (
        "import sys, turtlectl; print([m for m in ('zenoh', 'msgspec', 'turtlectl.runtime.node') if m in sys.modules])"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
    for name in turtlectl.__all__:
        assert getattr(turtlectl, name).__doc__, name
    with pytest.raises(AttributeError, match="no attribute 'Nope'"):
        turtlectl.Nope  # noqa: B018


def test_in_the_source_tree_our_folders_are_not_top_level_modules(tmp_path):
    """``make``'s editable install puts ``src/`` on sys.path, not the repository root: a user's
    ``import messages`` never finds ours."""
    code = "import importlib.util as u; print([n for n in ('messages', 'runtime', 'nodes', 'sim', 'cli') if u.find_spec(n)])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, check=True)
    assert out.stdout.strip() == "[]"
