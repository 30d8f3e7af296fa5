"""The layout's rules, read from the source with ``ast`` (no third-party tool):

* imports run one way, ``messages <- runtime <- sim <- nodes <- cli``: a package
  imports only packages to its left (and itself);
* the pure modules (wire contract, world model, kinematics, lidar, control law,
  scan geometry, goal logic, launch-file parsing) never import zenoh, not even
  through another module of ours;
* every import of ours is through ``turtlectl`` (``from turtlectl.messages import Twist``),
  never a bare ``messages``: a user's own ``messages.py`` would shadow that.

Modules are named here without their ``turtlectl.`` prefix (``runtime.node``).
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LAYERS = ["messages", "runtime", "sim", "nodes", "cli"]

#: modules that must stay free of zenoh (and so of I/O): plain functions over Structs and arrays
PURE = [
    "messages",  # every module of the package
    "runtime.config",
    "runtime.endpoint",
    "runtime.params",
    "runtime.exitcodes",
    "runtime.handles",
    "runtime.futures",
    "runtime.goal_reasons",
    "runtime.loader",
    "runtime.roles",
    "runtime.client.errors",  # what a client raises, and the exit code of each
    "runtime.client.checks",
    "runtime.client.credentials",
    "runtime.client.graph",
    "sim.kinematics",
    "sim.lidar",
    "sim.params",
    "nodes.control",
    "nodes.scan",
    "nodes.goal",
    "nodes.goal_machine",
    "nodes.driver",
    "nodes.surroundings",
    "nodes.battery",
    "nodes.params",
    "nodes.ros2_table",  # the ROS 2 bridge's table: launch --check validates it without DDS
    "nodes.ros2_mapping",  # turtlectl <-> ROS 2 conversions (cyclonedds types, no network)
    "nodes.kinds",
    "nodes.ros2_requests",  # the ROS 2 service types and requests, without DDS
    "cli.system.launchfile",
    "cli.system.compose",  # arguments and includes of launch files
    "cli.system.report",
    "cli.system.overrides",
    "cli.args",
    "cli.selection",
    "cli.verify.spec",
    "cli.verify.document",
    "cli.verify.report",
    "cli.tools.format",
    "cli.tools.rates",
    "cli.tools.plot",  # plot's model: KEY.FIELD, the numbers in a message
    "cli.tools.plot_window",  # plot's sliding window, its status line, the samples collected
    "cli.tools.keyboard",
    "cli.tools.interface_live",
    "cli.recording.bag",  # recordings: MCAP files, read and written without a session
    "cli.recording.reading",
    "cli.system.supervisor.supervision",  # the supervision policy: processes and clock come from outside
]


def imports_of(path: Path, name: str) -> set[str]:
    """Every module that ``path`` (module ``name``) imports, at any depth of its code (lazy
    imports in functions included); ours without their ``turtlectl.`` prefix, and a bare
    import of one of our packages as ``BARE:name``."""
    tree = ast.parse(path.read_text(), str(path))
    found: set[str] = set()
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative: resolve against this module's package
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module or ""
            found.add(stem)
            found.update(f"{stem}.{alias.name}" for alias in node.names)  # `from pkg import module`
    return {_ours(module) for module in found}


def _ours(module: str) -> str:
    if module.split(".")[0] in LAYERS:
        return f"BARE:{module}"
    return module.removeprefix("turtlectl.")


def all_modules(root: Path = ROOT) -> dict[str, set[str]]:
    """Module name -> the modules it imports, for every module of the five packages under ``root``."""
    graph: dict[str, set[str]] = {}
    for layer in LAYERS:
        for path in sorted((root / layer).rglob("*.py")):
            name = ".".join(path.relative_to(root).with_suffix("").parts).removesuffix(".__init__")
            graph[name] = imports_of(path, name)
    return graph


def layer_of(module: str) -> int | None:
    top = module.split(".")[0]
    return LAYERS.index(top) if top in LAYERS else None


def wrong_way(graph: dict[str, set[str]]) -> list[str]:
    """Imports that run to the right of the importing module's layer."""
    problems = []
    for module, imported in sorted(graph.items()):
        mine = layer_of(module)
        for target in sorted(imported):
            theirs = layer_of(target)
            if target.rpartition(".")[0] in imported and layer_of(target.rpartition(".")[0]) == theirs:
                continue  # `from sim.world import World`: reported once, as sim.world
            if mine is not None and theirs is not None and theirs > mine:
                problems.append(f"{module} imports {target} ({LAYERS[theirs]} is right of {LAYERS[mine]})")
    return problems


def zenoh_reached(graph: dict[str, set[str]], start: str) -> list[str] | None:
    """The chain of our imports by which ``start`` reaches zenoh, or None."""
    seen = {start}
    stack = [[start]]
    while stack:
        chain = stack.pop()
        for target in sorted(graph.get(chain[-1], ())):
            if target == "zenoh" or target.startswith("zenoh."):
                return [*chain, "zenoh"]
            if target in graph and target not in seen:
                seen.add(target)
                stack.append([*chain, target])
    return None


def pure_modules(graph: dict[str, set[str]]) -> list[str]:
    return sorted(m for m in graph if any(m == p or m.startswith(p + ".") for p in PURE))


def test_imports_run_one_way():
    assert wrong_way(all_modules()) == []


def bare_imports(graph: dict[str, set[str]]) -> list[str]:
    """Imports of our packages by their bare names (``from messages import Twist``)."""
    return [
        f"{m} imports {t.removeprefix('BARE:')}"
        for m, imported in sorted(graph.items())
        for t in sorted(imported)
        if t.startswith("BARE:")
    ]


def test_every_import_of_ours_goes_through_turtlectl():
    assert bare_imports(all_modules()) == []


@pytest.mark.parametrize("module", pure_modules(all_modules()))
def test_pure_modules_never_reach_zenoh(module):
    assert zenoh_reached(all_modules(), module) is None


def test_every_named_pure_module_exists():
    graph = all_modules()
    for name in PURE:
        assert any(m == name or m.startswith(name + ".") for m in graph), f"{name} is not a module any more"


def test_the_checks_catch_what_they_name(tmp_path):
    """The rules on a small tree that breaks both, so the two tests above can fail."""
    for layer in LAYERS:
        (tmp_path / layer).mkdir()
        (tmp_path / layer / "__init__.py").write_text("")
    (tmp_path / "runtime" / "node.py").write_text("import zenoh\nfrom turtlectl.sim.world import World\n")
    (tmp_path / "sim" / "kinematics.py").write_text("def f():\n    from turtlectl.runtime import node\n")
    (tmp_path / "nodes" / "patrol.py").write_text("from messages import Twist\n")
    graph = all_modules(tmp_path)
    assert wrong_way(graph) == ["runtime.node imports sim.world (sim is right of runtime)"]
    assert bare_imports(graph) == ["nodes.patrol imports messages", "nodes.patrol imports messages.Twist"]
    assert zenoh_reached(graph, "sim.kinematics") == ["sim.kinematics", "runtime.node", "zenoh"]


# -- comments and docs give the reason, not the tracker's history ---------------------------------

#: where code, tests and docs live: every .py below the packages, tests, benchmarks, examples and
#: docs; every .md of docs/ and the README; the Makefile, pyproject.toml and every .toml (launch files)
TEXT_FOLDERS = ["messages", "runtime", "sim", "nodes", "cli", "src", "tests", "bench", "examples", "docs"]
SKIPPED_PARTS = {".venv", "site", "__pycache__", "node_modules", ".git"}

#: a reader of the repository has no tracker: the word issue with a number (or an opening
#: parenthesis before it), a number after # in parentheses or after "see"/"fixes", and the
#: phrases that narrate a change instead of saying why the code is so
HISTORY = re.compile(
    r"\bissues?\s*#?\d+\b"
    r"|[(]issue\b"
    r"|(?:\(|\b(?:see|fixes|fixed|closes|closed|resolves|resolved)\s+)#\d+(?![\w-])"
    r"|\bold code\b"
    r"|\bbefore the fix\b"
    r"|\bpreviously\b"
    r"|\bfirst \w+ design\b"
    r"|\ba review found\b"
    r"|\bfound by a new user\b",
    re.IGNORECASE,
)


def text_files(root: Path = ROOT) -> list[Path]:
    """The files whose comments, docstrings and prose a reader reads."""
    found: set[Path] = set()
    for folder in TEXT_FOLDERS:
        for pattern in ("*.py", "*.md", "*.toml"):
            if pattern == "*.md" and folder != "docs":
                continue
            found.update((root / folder).rglob(pattern))
    found.update(root.glob("*.toml"))
    found.update(p for p in (root / "README.md", root / "Makefile") if p.exists())
    return sorted(p for p in found if not SKIPPED_PARTS.intersection(p.relative_to(root).parts))


def history_mentions(root: Path = ROOT) -> list[str]:
    """``file:line: text`` of every issue number or narrated history."""
    return [
        f"{path.relative_to(root)}:{number}: {line.strip()}"
        for path in text_files(root)
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if HISTORY.search(line)
    ]


def test_no_issue_numbers_or_history_in_code_tests_or_docs():
    """A comment or a doc says why the code is so in today's terms; an issue number points to a
    tracker no reader of the repository has."""
    found = history_mentions()
    assert not found, "say the reason instead:\n" + "\n".join(found)


def test_the_history_check_catches_what_it_names(tmp_path):
    """The patterns on a small tree, so the test above can fail (the words are split here so that
    this file passes it)."""
    issue, see = "iss" + "ue", "(see " + "#12)"
    (tmp_path / "runtime").mkdir()
    (tmp_path / "docs").mkdir()
    (tmp_path / "runtime" / "node.py").write_text(
        f"x = 1  # {issue} 22\ny = 2  # braking past the heading\n# {issue.capitalize()} #7: why\n"
    )
    (tmp_path / "docs" / "a.md").write_text(
        f"ok: payload #1 on k, [8](#8-write-your-own), {issue}r\nbad {see} and the old " + "code\n"
    )
    (tmp_path / "README.md").write_text(f"a goal ({issue} 22, item 4)\n")
    assert history_mentions(tmp_path) == [
        f"README.md:1: a goal ({issue} 22, item 4)",
        f"docs/a.md:2: bad {see} and the old " + "code",
        f"runtime/node.py:1: x = 1  # {issue} 22",
        f"runtime/node.py:3: # {issue.capitalize()} #7: why",
    ]
