"""Launch files made of launch files (pure: no zenoh): arguments, substitutions and includes,
as ROS 2's ``DeclareLaunchArgument``, ``LaunchConfiguration`` and ``IncludeLaunchDescription``::

    [arg.speed]                          # an argument: its default (and so its type), what it is for
    default = 0.5
    description = "the turtles' top speed, m/s"

    [[include]]                          # another launch file's nodes, in this system
    file = "turtle.toml"                 # relative to this file
    namespace = "turtle2"                # optional: its nodes drive turtle2 (ROS's PushRosNamespace)
    args = { max_speed = "$(arg speed)" }

``$(arg NAME)`` in any value of a file (``[arg]`` aside, where a default may use the arguments
above it) is that argument's value: a value that is only the substitution takes the value itself
(a number stays a number), one inside a longer text is written out in it.  The top file's
arguments are given on the command line (``--arg NAME=VALUE``), an included file's by its
``[[include]]``'s ``args``; an argument without a default must be given.  A value given is of
the default's type (an integer for a float is taken; on the command line a text argument takes
the text as written).

``compose`` reads a file and what it includes into ``Piece``s: each file's tables, arguments
substituted, ``arg`` and ``include`` taken out, with the chain of files that names it in errors
(``launch.toml -> include[1] (turtle2) turtle.toml``: each include by its index and namespace) and the namespace its include puts it in; cli.system.launchfile
validates them as one system.  Refused (``LaunchFileError``, exit 2): a file that includes itself
through any chain (``a.toml -> include[0] b.toml -> include[0] a.toml: include cycle``), an included file that does not
exist, an argument the file does not declare, and a second file writing ``[world]``, ``[limits]``
or ``[supervisor]`` (a launch has one of each, written in any one of its files).  An included
file's ``./file.py:Class`` and ``./program`` are relative to it (made absolute here); every
node runs in the top file's folder.
"""

from __future__ import annotations

import os
import re
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

import msgspec

from turtlectl.cli.system.placement import namespace_problem
from turtlectl.cli.system.report import (
    LaunchFileError,
    Parts,
    Report,
    declared_below,
    key_path,
    problem,
    raw_names,
    read_text,
    toml_text,
    toml_value,
)
from turtlectl.runtime.loader import is_file, is_target, suggestion

#: the system's own tables (``--set TABLE.KEY=VALUE`` reaches them): one file of a launch writes each
TABLES = ("world", "limits", "supervisor")
ARG_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
SUBSTITUTION = re.compile(r"\$\(([^()]*)\)")
UNCLOSED = re.compile(r"\$\((?![^()]*\))")  # a $( with no ) before the next ( or the end


class Argument(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """``[arg.NAME]``: an argument of the launch file (ROS's ``DeclareLaunchArgument``).
    ``$(arg NAME)`` in any value of the file is its value: ``--arg NAME=VALUE`` for the file
    launched, its ``[[include]]``'s ``args`` for an included one, else the default."""

    default: Any = None  # -: its value when none is given (none: it must be given); a value given is of its type
    description: str = ""  # -: what it is for (launch --check lists it)


class Include(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """``[[include]]``: another launch file's nodes in this system (ROS's
    ``IncludeLaunchDescription``, in a ``GroupAction`` with ``PushRosNamespace`` when
    ``namespace`` is given)."""

    file: str  # -: the launch file, relative to this one
    args: dict[str, Any] = msgspec.field(default_factory=dict)  # -: values for its [arg.NAME] arguments
    namespace: str = ""  # -: its nodes' namespace, the turtle they drive (none: each node's own, as written)


class ArgValue(msgspec.Struct, frozen=True, kw_only=True):
    """An argument as ``launch --check`` lists it: its value in this launch, and from where."""

    file: str  # the file that declares it (the chain of files, for an included one)
    name: str
    value: Any
    default: Any  # None: none
    description: str
    given: str  # "--arg", "include[0] of launch.toml", or "default"


class Piece(NamedTuple):
    """One file of a launch: its tables, ready for cli.system.launchfile.validate."""

    label: str  # names it in errors: the file, or the chain of includes (launch.toml -> include[1] (turtle2) t.toml)
    data: dict[str, Any]  # its tables, arguments substituted, without arg and include
    namespace: str = ""  # the namespace its include puts its nodes in
    sources: dict[str, str] = {}  # key path (node[1].params.rate) -> where its value came from (--arg speed ...)


class _Given(NamedTuple):
    """Values for a file's arguments, and how to name where they are written in errors."""

    values: dict[str, tuple[Any, str | None]]  # name -> (value, as the command line wrote it)
    origin: str  # "--arg", or "include[0] of launch.toml"
    error: Callable[[str | None, str], LaunchFileError]  # (argument or None, what is wrong) -> the error
    sources: dict[str, str] = {}  # name -> where its value came from, when written as $(arg ...) (include args)


def parse_args(items: list[str]) -> dict[str, str]:
    """``--arg NAME=VALUE`` items (spaces allowed around both; ROS's ``NAME:=VALUE`` too): NAME ->
    VALUE as written."""
    given: dict[str, str] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.removesuffix(":").strip()
        if not sep or not name:
            raise LaunchFileError(f"--arg {item!r}: write it as NAME=VALUE (an argument the launch file declares)")
        given[name] = text.strip()
    return given


def compose(text: str, source: str, given: dict[str, str] | None = None) -> tuple[list[Piece], list[ArgValue]]:
    """The launch file ``text`` (read from ``source``, which names it in errors and whose folder its
    includes are relative to) and every file it includes, as pieces; with each argument's value.
    ``given``: the command line's ``--arg`` values (parse_args)."""
    values = {name: (toml_value(written), written) for name, written in (given or {}).items()}

    def error(name: str | None, what: str) -> LaunchFileError:
        return LaunchFileError(
            f"--arg {name}={given[name]}: {what}" if given and name in given else f"{source}: {what}"
        )

    composer = _Composer()
    path = Path(source)
    sources = {name: f"--arg {name}" for name in values}
    composer.file(text, source, source, path, _Given(values, "--arg", error, sources), (path.resolve(),), "")
    for table in TABLES:
        writers = [piece.label for piece in composer.pieces if table in piece.data]
        if len(writers) > 1:
            raise LaunchFileError(
                f"{writers[1]}: {table}: {writers[0]} writes [{table}] too: a launch has one [{table}], "
                "in any one of its files"
            )
    return composer.pieces, composer.args


class _Composer:
    def __init__(self) -> None:
        self.pieces: list[Piece] = []
        self.args: list[ArgValue] = []

    def file(
        self, text: str, label: str, name: str, path: Path, given: _Given, chain: tuple[Path, ...], namespace: str
    ) -> None:
        """Add the file at ``path`` (its ``text``, ``name`` as written), then what it includes, depth first."""
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise LaunchFileError(f"{label}: not valid TOML: {exc}") from None
        report = Report(label, raw_names(data), override=False)
        below = data.get("include")
        values, origins = self.arguments(
            data.pop("arg", {}), report, given, name, lambda n: declared_below(n, below, path)
        )
        sources: dict[str, str] = {}
        data = _substitute(data, values, [], report, None, (origins, sources))
        includes: Any = data.pop("include", [])
        try:
            includes = msgspec.convert(includes, list[Include], strict=True)
        except msgspec.ValidationError as exc:
            parts, what = problem(exc, list[Include], includes)
            raise report.error(["include", *parts], what) from None
        if len(chain) > 1:
            _paths_from_top(data, path.parent, chain[0].parent)
        self.pieces.append(Piece(label, data, namespace, sources))
        for i, include in enumerate(includes):
            self.include(i, include, label, path, report, chain, namespace, sources)

    def include(
        self,
        i: int,
        include: Include,
        label: str,
        path: Path,
        report: Report,
        chain: tuple[Path, ...],
        namespace: str,
        sources: dict[str, str],
    ) -> None:
        """The ``i``-th ``[[include]]`` of the file at ``path`` (``sources``: where its values came from)."""
        target = path.parent / Path(include.file).expanduser()
        resolved = target.resolve()
        pushed = include.namespace.strip("/")
        inner = f"{label} -> include[{i}] {f'({pushed}) ' if pushed else ''}{include.file}"
        if resolved in chain:
            raise LaunchFileError(f"{inner}: include cycle (a file cannot include itself, nor through others)")
        if target.is_dir():
            raise report.error(["include", i, "file"], f"{include.file} is a folder: name a launch file in it")
        if not target.is_file():
            raise report.error(["include", i, "file"], f"{include.file}: no such file ({resolved})")
        text = read_text(target, inner)
        why = namespace_problem(pushed) if pushed else None
        if not why and namespace and pushed not in ("", namespace):
            why = f"{label} is in namespace {namespace!r} already: namespaces do not nest (a namespace is one turtle's)"
        if why:
            raise report.error(["include", i, "namespace"], why)

        def error(name: str | None, what: str) -> LaunchFileError:
            return report.error(["include", i, "args", *([name] if name else [])], what)

        values = {n: (v, None) for n, v in include.args.items()}
        written = {n: f"include[{i}].args.{n}" for n in include.args}
        origins = {n: f"{sources[w]} through {w}" for n, w in written.items() if w in sources}
        given = _Given(values, f"include[{i}] of {label}", error, {**written, **origins})
        self.file(text, inner, include.file, target, given, (*chain, resolved), pushed or namespace)

    def arguments(
        self, table: Any, report: Report, given: _Given, file: str, elsewhere: Callable[[str], str | None]
    ) -> tuple[dict[str, Any], dict[str, str]]:
        """The file's arguments (its ``[arg]`` table) with their values: ``given``, else each one's
        default (which may use the arguments above it); and where each value came from.  ``file``:
        the file as written; ``elsewhere(NAME)``: the include below it that declares NAME, if any."""
        form = 'a table, [arg.NAME] with default = ... and description = "..."'
        if not isinstance(table, dict):
            raise report.error(["arg"], f"write each argument as {form}")
        declared: dict[str, Argument] = {}
        for name, spec in table.items():
            if not isinstance(spec, dict):
                raise report.error(["arg", name], f"write it as {form}")
            try:
                declared[name] = msgspec.convert(spec, Argument, strict=True)
            except msgspec.ValidationError as exc:
                parts, what = problem(exc, Argument, spec)
                raise report.error(["arg", name, *parts], what) from None
        names = list(declared)
        for name in given.values:
            if name in declared:
                continue
            if below := elsewhere(name):
                raise given.error(
                    name,
                    f"{name} is an argument of {below}, not of {file}: a file sees only its own arguments; "
                    f'pass it through that include\'s args, as args = {{ {name} = "$(arg ...)" }}',
                )
            raise given.error(name, f"{file} declares no argument {name}{suggestion(name, names)} ({_listed(names)})")
        values: dict[str, Any] = {}
        origins: dict[str, str] = {}
        for name, argument in declared.items():
            if not ARG_NAME.match(name):
                raise report.error(["arg", name], f"{name!r} is not an argument name (letters, digits and _)")
            default = _substitute(argument.default, values, ["arg", name, "default"], report, names)
            if name in given.values:
                value, text = given.values[name]
                try:
                    value = _typed(value, default, text)
                except ValueError as exc:
                    raise given.error(name, f"{file}'s argument {name} is {exc}") from None
                origin = given.origin
                if name in given.sources:
                    origins[name] = given.sources[name]
            elif default is not None:
                value, origin = default, "default"
                origins[name] = f"arg.{name}'s default"
            elif given.origin == "--arg":
                raise report.error(["arg", name], f"no value: give one, --arg {name}=VALUE (it has no default)")
            else:
                raise given.error(None, f"{file}'s argument {name} has no default: give it, args = {{ {name} = ... }}")
            values[name] = value
            self.args.append(
                ArgValue(
                    file=report.label,
                    name=name,
                    value=value,
                    default=default,
                    description=argument.description,
                    given=origin,
                )
            )
        return values, origins


def _kind(value: Any) -> str:
    kinds = ((bool, "a boolean"), (int, "an integer"), (float, "a number"), (str, "a text"), (list, "a list"))
    return next((name for cls, name in kinds if isinstance(value, cls)), "a table")


def _typed(value: Any, default: Any, text: str | None) -> Any:
    """``value`` as an argument whose default is ``default`` takes it (``text``: as the command
    line wrote it); ValueError saying what it should be."""
    if default is None or type(value) is type(default):
        return value
    if isinstance(default, float) and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if isinstance(default, str) and text is not None:
        return text
    if isinstance(default, str) and isinstance(value, (int, float)):
        return _written(value)
    raise ValueError(f"{_kind(default)} (its default: {toml_text(default)}), not {_kind(value)} ({toml_text(value)})")


def _written(value: Any) -> str:
    """``value`` written inside a text: a text as it is, true/false, numbers as TOML writes them."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (str, int, float)):
        return str(value)
    raise ValueError(f"{_kind(value)} cannot be written inside a text")


_Trace = tuple[dict[str, str], dict[str, str]]  # (argument -> where its value came from, key path -> the same)


def _substitute(
    value: Any,
    values: dict[str, Any],
    at: Parts,
    report: Report,
    names: list[str] | None = None,
    trace: _Trace | None = None,
) -> Any:
    """``value`` (at key path ``at``) with every ``$(arg NAME)`` in it replaced by ``values[NAME]``;
    ``names``: every argument the file declares (those not in ``values`` yet come later);
    ``trace``: where each argument's value came from, and the key paths that take one, written in."""
    if isinstance(value, str):
        if UNCLOSED.search(value):
            raise report.error(at, f"{toml_text(value)}: unclosed $(...): write $(arg NAME)")
        found = [m[0][2:-1].split() for m in SUBSTITUTION.finditer(value)]
        used = [w[1] for w in found if len(w) == 2 and w[0] == "arg" and trace and w[1] in trace[0]]
        if trace and used:
            trace[1][key_path(at)] = ", ".join(dict.fromkeys(trace[0][n] for n in used))
        whole = SUBSTITUTION.fullmatch(value)
        if whole:
            return _lookup(whole[0], values, at, report, names)

        def written(match: re.Match[str]) -> str:
            try:
                return _written(_lookup(match[0], values, at, report, names))
            except ValueError as exc:
                raise report.error(at, f"{match[0]}: {exc}") from None

        return SUBSTITUTION.sub(written, value)
    if isinstance(value, list):
        return [_substitute(item, values, [*at, i], report, names, trace) for i, item in enumerate(value)]
    if isinstance(value, dict):
        return {
            _substitute(key, values, at, report, names): _substitute(item, values, [*at, key], report, names, trace)
            for key, item in value.items()
        }
    return value


def _lookup(written: str, values: dict[str, Any], at: Parts, report: Report, names: list[str] | None) -> Any:
    """The value ``$(arg NAME)`` (``written``) stands for."""
    words = written[2:-1].split()
    if len(words) != 2 or words[0] != "arg":
        raise report.error(at, f"{written}: not a substitution; write $(arg NAME), NAME an argument of the file")
    name = words[1]
    if name in values:
        return values[name]
    names = list(values) if names is None else names
    if name in names:
        raise report.error(at, f"{written}: a default may use only the arguments declared above it")
    raise report.error(
        at, f"{written}: the file declares no argument {name}{suggestion(name, names)} ({_listed(names)})"
    )


def _listed(names: list[str]) -> str:
    """A file's arguments as an unknown one's error lists them."""
    return f"its arguments: {', '.join(names)}" if names else "it declares none: add [arg.NAME]"


def _paths_from_top(data: dict[str, Any], folder: Path, top: Path) -> None:
    """An included file's ``./file.py:Class`` runs and ``./program`` cmds (relative to ``folder``,
    its own) written relative to the top file's folder, ``top`` (absolute when outside it): the
    plan's nodes are checked, and run, from there."""

    def moved(where: str) -> str:
        path = (folder / where).resolve()
        relative = os.path.relpath(path, top)
        return str(path) if relative.startswith("..") else f"./{relative}"

    nodes = list(data.get("node") or []) if isinstance(data.get("node"), list) else []
    for group in data.get("group") or [] if isinstance(data.get("group"), list) else []:
        if isinstance(group, dict) and isinstance(group.get("node"), list):
            nodes += group["node"]
    for node in nodes:
        if not isinstance(node, dict):
            continue
        run, cmd = node.get("run"), node.get("cmd")
        if isinstance(run, str) and is_target(run) and is_file(run.rpartition(":")[0]):
            where, _, name = run.rpartition(":")
            node["run"] = f"{moved(where)}:{name}"
        if isinstance(cmd, list) and cmd and isinstance(cmd[0], str) and "/" in cmd[0]:
            if not cmd[0].startswith(("/", "~")):
                node["cmd"] = [moved(cmd[0]), *cmd[1:]]
