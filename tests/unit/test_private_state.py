"""No module of ours reads or sets another module's private state: an attribute named with a
leading underscore is reached only through ``self``/``cls``, or from the module that defines it
(a class's helpers beside it).  A module that needs something of another's asks through a
public method (the node's core, runtime.core.NodeCore, is how the runtime's modules share a
node's queue, timers, time source and declarations).  Read from the source with ``ast``."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = [
    "messages",
    "runtime",
    "sim",
    "nodes",
    "cli",
    "src/turtlectl",
    "tests",
    "bench",
    "examples",
]  # tests too: they reach nodes through public or test-only APIs


def private_names(tree: ast.AST) -> set[str]:
    """The private names a module defines: its functions and classes, what it assigns to
    ``self``/``cls`` (``self._x = ...``) and its names (``_X = ...``)."""
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store) and _through_self(node):
            names.add(node.attr)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
    return {n for n in names if n.startswith("_") and not n.startswith("__")}


def _through_self(node: ast.Attribute) -> bool:
    return isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")


def private_reaches(root: Path = ROOT) -> list[str]:
    """``path:line: expression`` of each access (read or write) to a private attribute of ours
    that the module making it does not define, through anything but ``self`` or ``cls``."""
    trees = {
        path: ast.parse(path.read_text(), str(path)) for p in PACKAGES for path in sorted((root / p).rglob("*.py"))
    }
    defined = {path: private_names(tree) for path, tree in trees.items()}
    ours = set().union(*defined.values())  # a library's private name (os._exit) is not ours to judge
    found = []
    for path, tree in trees.items():
        for node in ast.walk(tree):
            if not isinstance(node, ast.Attribute) or node.attr not in ours or node.attr in defined[path]:
                continue
            if _through_self(node):
                continue
            found.append(f"{path.relative_to(root)}:{node.lineno}: {ast.unparse(node)}")
    return found


def test_no_module_reaches_into_another_modules_private_state():
    assert private_reaches() == []
