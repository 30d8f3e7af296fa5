"""How message types are named (pure): ``package/Name``, as ROS names them by package
(``turtlesim/msg/Pose``), so that two packages' ``TurtleStatus`` coexist.

A type's full name is its wire tag: the ``"type"`` member of every payload and the schema in
the sample encoding ``application/msgpack;package/Name``.  turtlectl's own types are package
``turtlectl`` (``turtlectl/Pose``).  A user's ``class TurtleStatus(Message, tag="TurtleStatus")``
takes its package from where it is declared: the top-level package or module of its
``__module__`` (``capstone_msgs.types`` -> ``capstone_msgs/TurtleStatus``), the file's stem for a
script run as ``__main__`` or loaded from a file; a tag with one slash
(``tag="capstone_interfaces/TurtleStatus"``) is taken as it is.  Both parts are Python
identifiers; the package ``turtlectl`` belongs to the built-ins.

Where a name must be one Zenoh key chunk (liveliness tokens, type description keys) it is
written with a dot, as a namespaced node name is (``capstone_msgs.TurtleStatus``: keys.type_chunk).
A user may type the short name (``TurtleStatus``) wherever it names one known type only
(``lookup``).
"""

from __future__ import annotations

import re
import sys
from collections.abc import Iterable
from pathlib import Path

BUILTIN_PACKAGE = "turtlectl"
#: the attribute a class rebuilt from a description (messages.described.struct_from) carries; its
#: name is the one the description gives, as it is (a recording's legacy bare name included)
REBUILT = "__turtlectl_rebuilt__"
#: modules whose types are turtlectl's own (the package's modules, and the classes a tool rebuilds from a description)
_OWN_MODULE = re.compile(r"^turtlectl(\.|$)")
_FILE_MODULE = re.compile(r"^_turtlectl_file_\d+_")  # runtime.loader's name for a file whose stem is taken


class TypeNameError(ValueError):
    """A message type's name that does not follow the rule (``package/Name``, identifiers)."""


class AmbiguousType(ValueError):
    """A short name that more than one known type has; ``choices``: their full names."""

    def __init__(self, name: str, choices: list[str]):
        self.choices = choices
        super().__init__(f"type {name!r} is ambiguous: write one of {', '.join(choices)}")


def package_of(module: str) -> str:
    """The package a type declared in ``module`` belongs to: the top-level name of the module,
    the file's stem for a script (``__main__``) or a file the runtime loaded, made an identifier."""
    if module == "__main__" or _FILE_MODULE.match(module):
        file = getattr(sys.modules.get(module), "__file__", None)
        top = Path(file).stem if file else _FILE_MODULE.sub("", module) or "__main__"
    else:
        top = module.split(".", 1)[0]
    top = re.sub(r"\W", "_", top)
    return "_" + top if top[:1].isdigit() else top


def full_name(tag: str, module: str) -> str:
    """The full name of a type declared in ``module`` with wire tag ``tag`` (or its class name):
    ``tag`` as it is when it has a package, else the module's package and ``tag``.
    TypeNameError when either part is not an identifier or ``turtlectl`` is claimed by another
    package's module."""
    package, slash, short = tag.rpartition("/")
    if not slash:
        package = package_of(module)
    if not package.isidentifier() or not short.isidentifier():
        raise TypeNameError(
            f"message type name {tag!r}: write Name or package/Name (each a Python identifier, "
            f"e.g. capstone_msgs/TurtleStatus)"
        )
    if package == BUILTIN_PACKAGE and not _OWN_MODULE.match(module):
        raise TypeNameError(f"message type name {tag!r}: the package 'turtlectl' is turtlectl's own; name yours")
    return f"{package}/{short}"


def short_name(name: str) -> str:
    """``TurtleStatus`` for ``capstone_msgs/TurtleStatus`` (a name without a package as it is)."""
    return name.rpartition("/")[2]


def names(name: str, full: str) -> bool:
    """Whether ``name`` as a person wrote it (``package/Name`` or, for one type already known, the
    short ``Name``) names the type whose full name is ``full``."""
    return name == full or ("/" not in name and name == short_name(full))


def is_full(name: str) -> bool:
    """Whether ``name`` is a well-formed full name (``package/Name``, identifiers)."""
    package, slash, short = name.partition("/")
    return bool(slash) and package.isidentifier() and short.isidentifier()


def lookup(name: str, known: Iterable[str]) -> str | None:
    """The full name among ``known`` that ``name`` means: that full name (case aside), else the
    one type whose short name it is; None for none; AmbiguousType when several types have it."""
    names = sorted(set(known))
    lower = name.lower()
    exact = [n for n in names if n.lower() == lower]
    if exact:
        return name if name in exact else exact[0]
    if "/" in name:
        return None
    matches = [n for n in names if short_name(n).lower() == lower]
    if len(matches) > 1:
        raise AmbiguousType(name, matches)
    return matches[0] if matches else None
