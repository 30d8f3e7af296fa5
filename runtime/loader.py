"""A user's node class from its ``run`` target (pure: no zenoh of its own, though the user's
module may import it).

A target names a class as ``module:Class`` (``mypkg.patrol:Patrol``: found in a base folder,
the launch file's, first, then on ``sys.path``/``PYTHONPATH``) or ``file.py:Class``
(``./patrol.py:Patrol``; relative to the base folder, its own folder then first on sys.path).
The node process runs in the base folder (``python -m`` puts it first on its sys.path): the
supervisor's check and the node find the same module.  The class is a node if it has a ``Params`` attribute: its
parameter Struct (a ``msgspec.Struct`` subclass), as ``class Patrol: Params = PatrolParams``.

Everything that makes a target unusable raises ``LoadError`` with one line saying why (the
file and line of an ImportError or SyntaxError); an exception the module's own code raises
while it is imported is ``ImportRaised`` (a ``LoadError`` too), its cause kept for the
traceback.
"""

from __future__ import annotations

import difflib
import importlib
import importlib.util
import re
import sys
import traceback
from collections.abc import Iterable
from pathlib import Path
from types import ModuleType

import msgspec

from turtlectl.runtime.client.errors import BadInput

_MODULE_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$")
_CLASS_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
#: the files loaded by path, by absolute path (a file is imported once per process)
_FILES: dict[Path, ModuleType] = {}


class LoadError(BadInput, ValueError):
    """A target that names no usable node class; str() is the one line saying why (exit code 2)."""


class ImportRaised(LoadError):
    """The module's own code raised while it was imported; ``__cause__`` is that exception."""


def nearest(word: str, candidates: Iterable[str]) -> str | None:
    """The candidate nearest to ``word`` (a typo's: ``navigatr``, ``navigator``), or None."""
    close = difflib.get_close_matches(word, list(candidates), n=1, cutoff=0.6)
    return close[0] if close else None


def suggestion(word: str, candidates: Iterable[str]) -> str:
    """``; did you mean X?`` for the candidate nearest to ``word``, or nothing: the one way a
    launch file's keys, a node's parameters, node kinds and running nodes' names suggest."""
    near = nearest(word, candidates)
    return f"; did you mean {near}?" if near else ""


def is_target(run: str) -> bool:
    """Whether ``run`` names a class (``module:Class``, ``file.py:Class``) rather than a built-in kind."""
    return ":" in run


def is_file(where: str) -> bool:
    return where.endswith(".py") or "/" in where or "\\" in where


def absolute(target: str, base: Path) -> str:
    """``target`` with a file made absolute (against ``base``), so that it names the same class
    from any working directory; a module target unchanged."""
    where, _, name = target.rpartition(":")
    if not is_file(where):
        return target
    return f"{(base / where).resolve()}:{name}"


def load(target: str, base: Path | None = None) -> tuple[type, type[msgspec.Struct]]:
    """The node class ``target`` names and its parameter Struct (its ``Params``)."""
    where, _, name = target.rpartition(":")
    if not where or not _CLASS_RE.match(name):
        raise LoadError(f"{target!r}: write it as module:Class or ./file.py:Class")
    module = _load_file(where, base or Path.cwd()) if is_file(where) else _load_module(where, base or Path.cwd())
    shown = where if not is_file(where) else Path(where).name
    cls = getattr(module, name, None)
    if cls is None:
        classes = [k for k, v in vars(module).items() if isinstance(v, type) and v.__module__ == module.__name__]
        hint = suggestion(name, classes)
        listed = f" (its classes: {', '.join(classes)})" if classes else " (it defines no class)"
        raise LoadError(f"{shown} has no {name}{hint}{listed}")
    if not isinstance(cls, type):
        raise LoadError(f"{shown}:{name} is not a class (a {type(cls).__name__})")
    params = getattr(cls, "Params", None)
    if params is None:
        raise LoadError(
            f"{shown}:{name} is not a node class: it has no Params (give it its parameter Struct: Params = MyParams)"
        )
    if not (isinstance(params, type) and issubclass(params, msgspec.Struct)):
        raise LoadError(f"{shown}:{name}.Params is not a msgspec.Struct class (its parameters)")
    return cls, params


def _load_module(where: str, base: Path) -> ModuleType:
    if not _MODULE_RE.match(where):
        raise LoadError(f"{where!r} is not a module name (write a file as ./{where}.py)")
    first_on_path(base)  # the project's folder, as the node's own process has it (its working folder)
    try:
        return importlib.import_module(where)
    except ModuleNotFoundError as exc:
        if exc.name and (where == exc.name or where.startswith(exc.name + ".")):
            raise LoadError(
                f"cannot import {where}: no module named {exc.name!r} (in {base} or on PYTHONPATH)"
            ) from None
        raise LoadError(f"cannot import {where}: {_why(exc)}") from None
    except (ImportError, SyntaxError) as exc:
        raise LoadError(f"cannot import {where}: {_why(exc)}") from None
    except Exception as exc:  # the module's own code, at import: kept for its traceback
        raise ImportRaised(f"importing {where} raised {_why(exc)}") from exc


def first_on_path(folder: Path) -> None:
    """Put ``folder`` (a project's) first on sys.path, once: its modules import before any other's."""
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))


def _load_file(where: str, base: Path) -> ModuleType:
    path = (base / where).resolve()
    if path in _FILES:
        return _FILES[path]
    if not path.is_file():
        raise LoadError(f"no file {where} (looked for {path})")
    stem = path.stem
    # its own name when free (as `python patrol.py` would let its siblings `import patrol`), never
    # one already taken (ours, or a library's)
    name = stem if stem.isidentifier() and stem not in sys.modules else f"_turtlectl_file_{len(_FILES)}_{stem}"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise LoadError(f"cannot import {where}: not a Python file")
    module = importlib.util.module_from_spec(spec)
    # its siblings import first, as `python patrol.py` gives them (a user's own messages.py or
    # nodes/ included: ours are turtlectl.messages and turtlectl.nodes, never in their way)
    first_on_path(path.parent)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except (ImportError, SyntaxError) as exc:
        del sys.modules[name]
        raise LoadError(f"cannot import {where}: {_why(exc)}") from None
    except Exception as exc:
        del sys.modules[name]
        raise ImportRaised(f"importing {where} raised {_why(exc)}") from exc
    _FILES[path] = module
    return module


def _why(exc: BaseException) -> str:
    """The exception's type and message, with the file and line it comes from."""
    if isinstance(exc, SyntaxError) and exc.filename:
        return f"{type(exc).__name__}: {exc.msg} ({Path(exc.filename).name}, line {exc.lineno})"
    frames = [f for f in traceback.extract_tb(exc.__traceback__) if not f.filename.startswith("<frozen")]
    mine = [f for f in frames if Path(f.filename).resolve() != Path(__file__).resolve()]
    where = f" ({Path(mine[-1].filename).name}, line {mine[-1].lineno})" if mine else ""
    return f"{type(exc).__name__}: {exc}{where}"


def type_clash(folder: Path) -> str | None:
    """Two different message classes under one full name among those declared in modules under
    ``folder`` (a launch file's project): what a node using both would die of at its start
    (codec.TypeClash), said before anything starts; None when there is none."""
    from turtlectl.messages import Message
    from turtlectl.messages.codec import type_name
    from turtlectl.messages.naming import REBUILT

    root = folder.resolve()
    by_name: dict[str, list[type]] = {}
    todo = list(Message.__subclasses__())
    while todo:
        cls = todo.pop()
        todo.extend(cls.__subclasses__())
        file = getattr(sys.modules.get(cls.__module__), "__file__", None)
        if getattr(cls, REBUILT, False) or not file or not Path(file).resolve().is_relative_to(root):
            continue
        by_name.setdefault(type_name(cls), []).append(cls)
    for name, classes in sorted(by_name.items()):
        if len(classes) > 1:
            where = " and ".join(sorted(f"{c.__module__}.{c.__qualname__}" for c in classes))
            return f'two message types named {name!r}: {where} (give one another name or package: tag="package/Name")'
    return None
