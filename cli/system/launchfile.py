"""Launch files: TOML, validated completely before anything starts (pure: no zenoh).

A launch file has a ``[world]`` table (size, obstacles), a ``[limits]`` table
(the robot's speed limits), a ``[supervisor]`` table and one ``[[node]]`` table
per process.  Every mistake is reported as ``LaunchFileError`` naming the file
and the exact key path, with the node's name when there is one, e.g.
``launch.toml: node[1] (navigator).params.goal_timeot: unknown key; did you mean goal_timeout?``.

Besides each value's own type and range (the Structs in nodes/params.py,
sim/params.py and messages/world.py), the file is checked as a whole: the spawn lies
in the world and outside every obstacle, no obstacle covers the world or lies
outside it, no two nodes claim the same (one node of each built-in kind: they use fixed
keys; a user's kind claims only what its class declares), and the navigator's scan_timeout
outlasts the scan period.

A ``run`` is a built-in kind or a user's node class (``module:Class``, ``./file.py:Class``
relative to the launch file), imported here to validate its parameters (nodes.kinds.kind_of).
A node's ``remap`` (ROS's remappings) is checked here against the keys its kind uses.

A launch file may declare arguments and include other launch files (``[arg.NAME]``,
``$(arg NAME)``, ``[[include]]``: cli.system.compose, which reads them into pieces, one per
file, that ``validate`` checks as one system; errors name the chain of files,
``launch.toml -> include[1] (turtle2) robots/turtle.toml: node[0] (turtle2/navigator).params.goal_timeout: ...``; a value from an argument says which, ``(from --arg speed through include[1].args.max_speed)``).

Overrides (``launch --set``, ``run -p``, ``param set``) and the ``--only``/``--exclude`` selection are in cli.system.overrides.
"""

from __future__ import annotations

import os
import re
import shutil
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated, Any

import msgspec

from turtlectl.cli.system.compose import TABLES as TABLES  # also for cli.system.overrides
from turtlectl.cli.system.compose import Argument, ArgValue, Include, Piece, compose, parse_args
from turtlectl.cli.system.placement import check_spawn, check_turtles, check_world, namespace_problem, remap_problem
from turtlectl.cli.system.report import LaunchFileError as LaunchFileError  # also for the other modules
from turtlectl.cli.system.report import Report as Report  # also for cli.system.overrides
from turtlectl.cli.system.report import problem, raw_names, read_text
from turtlectl.messages.keys import FIRST_TURTLE
from turtlectl.messages.world import Limits, World
from turtlectl.nodes.kinds import KindError, NodeKind, kind_of
from turtlectl.runtime.loader import first_on_path, is_target, type_clash
from turtlectl.runtime.loader import suggestion as suggestion  # also for cli.system.overrides, cli.tools
from turtlectl.runtime.params import validation_parts as validation_parts  # also for cli.tools.build
from turtlectl.runtime.roles import claims_of, interface_of

#: the launch file that comes with turtlectl: the whole system on one machine
PACKAGED_LAUNCH = Path(__file__).resolve().parent / "launch.toml"
NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_\-]*$")
_INCLUDE = re.compile(r"include\[\d+\] (\([^)]*\) )?")  # in a chain of files: which include of the file before

Delay = Annotated[float, msgspec.Meta(ge=0.0, le=3600.0)]
StopWait = Annotated[float, msgspec.Meta(gt=0.0, le=60.0)]
Respawns = Annotated[int, msgspec.Meta(ge=0, le=1_000_000)]
Kept = Annotated[int, msgspec.Meta(ge=0, le=10_000)]
Argv = list[str]
Remaps = dict[str, str]  # a key as the node's code writes it -> the key it uses instead


class NodeEntry(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """One process to run.  A node that exits for good (no respawn, its respawns used up, or
    start_tries starts in a row that failed before it was ready) stops the system if it is
    required (exit code 1).  An exit with code 2 (its configuration cannot be used) or 4
    (another process holds what it claims) is never respawned: respawning cannot help (see the
    exit codes)."""

    name: str  # -: letters, digits, _ and -; unique in its namespace (its full name, namespace/name, in the system)
    namespace: str = ""  # -: the turtle it drives, its keys' prefix, e.g. "turtle2": navigate_to is turtle2/navigate_to and turtle1/pose is turtle2/pose (in a [[group]]: the group's); none: turtle1's, with the seed's keys (navigate_to, robot/status), or "turtle1" as any turtle's
    run: str = ""  # -: a built-in kind (sim, navigator, status_monitor, obstacle_detector, ros2_bridge, web: nodes/kinds.py KINDS) or a node class (pkg.mod:Class, ./file.py:Class); or cmd
    cmd: Argv = []  # -: instead of run, any program and its arguments, e.g. ["./driver", "--port", "/dev/ttyUSB0"] (./ relative to the launch file; a bare name from PATH); ready once started; no params
    params: dict[str, Any] = msgspec.field(default_factory=dict)  # -: the kind's parameters (below), a class's Params
    remap: Remaps = {}  # -: ROS's remappings, { "turtle1/cmd_vel" = "safety/cmd_vel" }: a key as the node's code writes it (or absolute: /turtle2/cmd_vel) -> the key it uses instead, both resolved in its namespace
    use_sim_time: bool = False  # -: its timers, timeouts and stamps follow the simulator's clock key, not the machine's (ROS's use_sim_time; launch --time-scale and launch --use-sim-time set it on every node)
    required: bool = False  # -: when it exits for good the whole system stops, exit code 1
    respawn: bool = False  # -: start it again when it exits
    respawn_delay: Delay = 1.0  # s: before the first respawn; twice as long after each crash in a row
    respawn_delay_max: Delay = 30.0  # s: the longest wait between respawns
    respawn_max: Respawns = 5  # -: respawns in a row at most (0: no limit); a run of 10 s restarts the count
    start_tries: Respawns = 3  # -: starts in a row that may fail before it is ready (a constructor that raises, a module that cannot import), then it is not respawned (0: no limit); systemd's start limit


class SupervisorSettings(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """How the supervisor stops the system: SIGINT to every node, then SIGTERM to those left,
    then SIGKILL; and how many run folders of logs it keeps."""

    sigint_timeout: StopWait = 2.0  # s: wait after SIGINT before SIGTERM
    sigterm_timeout: StopWait = 1.0  # s: wait after SIGTERM before SIGKILL
    keep_logs: Kept = 20  # -: run folders of logs kept, this run's included; older ones go at launch (0: all)


class Group(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    """Nodes that share a namespace (ROS's ``PushRosNamespace``): ``[[group]]`` with
    ``namespace = "turtle2"`` and its ``[[group.node]]`` tables, one navigator, status monitor
    and obstacle detector per turtle."""

    namespace: str  # -: the group's nodes' namespace, e.g. "turtle2" (the turtle they drive)
    node: list[NodeEntry] = msgspec.field(default_factory=list)  # -: as [[node]]


class LaunchFile(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    node: list[NodeEntry] = msgspec.field(default_factory=list)
    group: list[Group] = msgspec.field(default_factory=list)
    arg: dict[str, Argument] = msgspec.field(default_factory=dict)  # (cli.system.compose takes them out)
    include: list[Include] = msgspec.field(default_factory=list)
    world: World = msgspec.field(default_factory=World)
    limits: Limits = msgspec.field(default_factory=Limits)
    supervisor: SupervisorSettings = msgspec.field(default_factory=SupervisorSettings)


class LaunchPlan(msgspec.Struct, kw_only=True):
    """A validated launch file: each entry's params already checked against its kind."""

    source: str
    launch: LaunchFile
    params: dict[str, dict[str, Any]]  # node name -> full parameters (defaults filled in)
    kinds: dict[str, NodeKind] = msgspec.field(default_factory=dict)  # node name -> what its run names
    commands: dict[str, list[str]] = msgspec.field(default_factory=dict)  # cmd node -> its argv, program resolved
    folder: str = ""  # the launch file's folder: where user nodes and programs run, and module:Class is found first
    #: the file's nodes that --only/--exclude leave to another host (a --secure system makes their logins)
    elsewhere: dict[str, NodeKind] = msgspec.field(default_factory=dict)
    #: node name -> its remap, for every node of the file that has one (those left elsewhere too)
    remaps: dict[str, dict[str, str]] = msgspec.field(default_factory=dict)
    args: list[ArgValue] = msgspec.field(default_factory=list)  # each file's arguments, with their values


# -- validation ----------------------------------------------------------------
def validate(
    data: Any, source: str, report: Report, base: Path | None = None, included: Sequence[Piece] = ()
) -> LaunchPlan:
    """The whole launch file, each value and then the file as a whole; a ``./file.py:Class``
    run is relative to ``base`` (default: the folder of ``source``).  ``included``: the files
    its ``[[include]]``s bring (cli.system.compose), checked as one system with it: each file's
    own errors name it (its chain), [world], [limits] and [supervisor] are the one file's that
    writes them."""
    base = base if base is not None else Path(source).resolve().parent
    entries: list[NodeEntry] = []
    origins: list[str] = []
    labels: list[str] = []  # the file (chain) of each node written in an included file
    sources: list[dict[str, str]] = []  # where the values of each node's file came from (its arguments)
    files: list[tuple[Piece, LaunchFile, Report]] = []
    for piece in (Piece(report.label, data), *included):
        own = report if not files else Report(piece.label, raw_names(piece.data), override=False)
        own.sources = piece.sources if files else report.sources
        try:
            launch = msgspec.convert(piece.data, LaunchFile, strict=True)
        except msgspec.ValidationError as exc:
            raise own.error(*problem(exc, LaunchFile, piece.data)) from None
        more, written = _flattened(launch, own, piece.namespace)
        entries, origins = entries + more, origins + written
        labels += [piece.label if files else ""] * len(more)
        sources += [own.sources] * len(more)
        files.append((piece, launch, own))
    report.names, report.origins, report.files = [e.name for e in entries], origins, labels
    report.node_sources = sources
    if not entries:
        raise report.error(["node"], "the launch file lists no node (no [[node]] and no [[group]] with one)")

    def owner(table: str) -> tuple[LaunchFile, Report]:
        """The file that writes ``table`` (compose lets one only), else the top file (its defaults)."""
        return next(((f, r) for p, f, r in files if isinstance(p.data, dict) and table in p.data), files[0][1:])

    (world, world_report), limits, supervisor = owner("world"), owner("limits")[0], owner("supervisor")[0]
    launch = msgspec.structs.replace(
        files[0][1],
        node=entries,
        group=[],
        world=world.world,
        limits=limits.limits,
        supervisor=supervisor.supervisor,
    )
    first_on_path(base)  # the project's modules, as its nodes import them (a user's type a bridge row names)
    seen: dict[str, int] = {}
    kinds: dict[tuple[str, str], int] = {}  # (namespace, built-in kind) -> its node's index
    claimed: dict[Any, int] = {}  # claim (resolved in the node's namespace) -> the index of the node that claims it
    params: dict[str, dict[str, Any]] = {}
    resolved: dict[str, NodeKind] = {}
    commands: dict[str, list[str]] = {}
    for i, entry in enumerate(launch.node):
        if entry.name in seen:
            j = seen[entry.name]
            file_j, file_i = (_INCLUDE.sub("", report.files[k]) for k in (j, i))  # the file, whichever include
            twice = file_j and (file_j, report.origins[j]) == (file_i, report.origins[i])
            why = f"{report.place(j, i)} has it"
            why = "its file is included twice: give each [[include]] a namespace" if twice else why
            raise report.error(["node", i, "name"], f"duplicate node name {entry.name!r} ({why})")
        seen[entry.name] = i
        if bool(entry.run) == bool(entry.cmd):
            which = "both run and cmd" if entry.run else "neither run nor cmd"
            raise report.error(["node", i], f"{which}: give run (a node kind or class) or cmd (a program)")
        if entry.cmd:
            if entry.params:
                raise report.error(["node", i, "params"], "a cmd node has no parameters (pass them in its cmd)")
            if entry.remap:
                raise report.error(["node", i, "remap"], "a cmd node has no keys of a turtlectl node to remap")
            commands[entry.name] = [_program(entry.cmd, base, report.error, i), *entry.cmd[1:]]
            params[entry.name] = {}
            continue
        try:
            kind = kind_of(entry.run, base)
        except KindError as exc:
            raise report.error(["node", i, "run"], str(exc)) from None
        # a user's node class brings the project's message types, which may clash; a kind of the registry
        # (forked, or the web page's, exec'd) brings only ours
        clash = None if kind.builtin or not is_target(entry.run) else type_clash(base)
        if clash:
            raise report.error(["node", i, "run"], clash)
        if entry.run == "sim" and entry.namespace:
            raise report.error(
                ["node", i, "namespace"],
                "the simulator serves every turtle of the world: it runs outside any namespace "
                "(its turtles go in its params.turtles, or come with turtlectl spawn)",
            )
        # the node's keys, for its remap's FROMs (none: nothing to check them against)
        declared = interface_of(entry.name, kind.interface) if entry.remap and kind.interface is not None else None
        wrong = remap_problem(entry.remap, entry.namespace, declared)
        if wrong:
            raise report.error(["node", i, "remap", f'"{wrong[0]}"'], wrong[1])
        # "one of each kind" per namespace, for the kinds that claim something (unless remapped apart)
        for claim in claims_of(entry.name, kind.claims, entry.remap):
            if claim in claimed:
                j = claimed[claim]
                other = launch.node[j]
                where = f" in namespace {entry.namespace!r}" if entry.namespace else ""
                if other.run == entry.run:
                    why = f"a second {entry.run!r} node{where} ({report.place(j, i)} ({other.name}) is one): both would {claim.phrase()}; "
                    raise report.error(
                        ["node", i, "run"],
                        why + "a namespace runs one of each kind (give each turtle's nodes its own namespace)",
                    )
                raise report.error(
                    ["node", i, "run"],
                    f"{report.place(j, i)} ({other.name}) already claims what it claims: both would {claim.phrase()}",
                )
            claimed[claim] = i
        if kind.builtin:
            kinds[(entry.namespace, entry.run)] = i
        resolved[entry.name] = kind
        try:
            typed = msgspec.convert(entry.params, kind.params, strict=True)
        except msgspec.ValidationError as exc:
            parts, what = problem(exc, kind.params, entry.params)
            raise report.error(["node", i, "params", *parts], what) from None
        params[entry.name] = msgspec.to_builtins(typed)
        narrow = getattr(typed, "narrow_interface", None)  # what these parameters need of the kind's Interface
        if callable(narrow) and kind.interface is not None:
            resolved[entry.name] = msgspec.structs.replace(kind, interface=narrow(kind.interface))

    for (namespace, run), i in kinds.items():  # turtle1's nodes run outside any namespace or in turtle1's: not both
        if namespace == FIRST_TURTLE and ("", run) in kinds:
            j = kinds[("", run)]
            raise report.error(
                ["node", i, "namespace"],
                f"a second {run!r} node driving {FIRST_TURTLE} ({report.place(j, i)} ({launch.node[j].name}) runs "
                f"outside any namespace, which is {FIRST_TURTLE}'s too): run {FIRST_TURTLE}'s nodes in one of them",
            )
    check_world(launch.world, world_report)
    if ("", "sim") in kinds:
        i = kinds[("", "sim")]
        check_spawn(launch.world, i, params[launch.node[i].name], report)
        check_turtles(launch.world, i, params[launch.node[i].name], report)
    for (namespace, run), i in kinds.items():
        if run != "navigator" or (namespace, "obstacle_detector") not in kinds:
            continue
        navigator = params[launch.node[i].name]
        detector = launch.node[kinds[(namespace, "obstacle_detector")]]
        rate = params[detector.name]["rate"]
        if navigator["scan_timeout"] <= 1.0 / rate:
            raise report.error(
                ["node", i, "params", "scan_timeout"],
                f"{navigator['scan_timeout']:g} s is not longer than the scan period of {detector.name} "
                f"({1.0 / rate:g} s at {rate:g} Hz): obstacles would be forgotten between scans",
            )
    remaps = {e.name: e.remap for e in launch.node if e.remap}
    return LaunchPlan(
        source=source,
        launch=launch,
        params=params,
        kinds=resolved,
        commands=commands,
        folder=str(base),
        remaps=remaps,
    )


def _flattened(launch: LaunchFile, report: Report, pushed: str = "") -> tuple[list[NodeEntry], list[str]]:
    """Every node of the file, a group's nodes in its namespace (the file's nodes in ``pushed``,
    the namespace its include puts it in), each named by its full name (``turtle2/navigator``);
    and where each is written (``node[1]``, ``group[0].node[2]``)."""
    entries: list[NodeEntry] = []
    origins: list[str] = []
    written = [(f"node[{i}]", pushed, entry) for i, entry in enumerate(launch.node)]
    for g, group in enumerate(launch.group):
        where = f"group[{g}]"
        group = msgspec.structs.replace(group, namespace=group.namespace.strip("/"))  # ROS writes /turtle2
        why = namespace_problem(group.namespace)
        if not why and pushed and group.namespace != pushed:
            why = f"the file is included in namespace {pushed!r}: namespaces do not nest (a namespace is one turtle's)"
        if why:
            raise LaunchFileError(f"{report.label}: {where}.namespace: {why}")
        written += [(f"{where}.node[{i}]", group.namespace, entry) for i, entry in enumerate(group.node)]
    for origin, outer, entry in written:
        entry = msgspec.structs.replace(entry, namespace=entry.namespace.strip("/"))
        label = f"{report.label}: {origin}" + (f" ({entry.name})" if entry.name else "")
        why = namespace_problem(entry.namespace) if entry.namespace else None
        if not why and outer and entry.namespace not in ("", outer):
            whose = "its [[include]]'s namespace" if origin.startswith("node") else "its group's namespace"
            why = f"the node is in {whose} {outer!r} (a namespace is one turtle's)"
        if why:
            raise LaunchFileError(f"{label}.namespace: {why}")
        namespace = outer or entry.namespace
        short = entry.name.removeprefix(f"{namespace}/") if namespace else entry.name  # written again: full
        if not NAME_RE.match(short):
            raise LaunchFileError(
                f"{label}.name: {short!r} is not a valid name (letters, digits, _ and -; "
                'a namespace goes in namespace = "...", or a [[group]])'
            )
        if short in TABLES and not namespace:
            raise LaunchFileError(
                f"{label}.name: {short!r} is reserved (--set {short}.KEY=VALUE sets the [{short}] table)"
            )
        full = f"{namespace}/{short}" if namespace else short
        entries.append(msgspec.structs.replace(entry, name=full, namespace=namespace))
        origins.append(origin)
    return entries, origins


def _program(cmd: list[str], base: Path, error: Any, i: int) -> str:
    """The absolute path of ``cmd``'s program: with a / it is a file (relative to ``base``), a
    bare name is looked up on PATH; it must exist and be executable (``error`` says why not)."""
    if not cmd[0]:
        raise error(["node", i, "cmd"], "name a program: cmd is a list, the program then its arguments")
    program = cmd[0]
    if "/" not in program:
        found = shutil.which(program)
        if found is None:
            raise error(["node", i, "cmd"], f"{program}: no such program on PATH")
        return found
    path = Path(program).expanduser()
    path = path if path.is_absolute() else base / path
    if not path.exists():
        raise error(["node", i, "cmd"], f"{program} does not exist ({path})")
    if path.is_dir() or not os.access(path, os.X_OK):
        raise error(["node", i, "cmd"], f"{program} is not executable")
    return str(path)


def parse_launch(text: str, source: str = "launch.toml", args: list[str] | None = None) -> LaunchPlan:
    """Parse and validate launch-file text and the files it includes (relative to ``source``'s
    folder); ``source`` names it in error messages; ``args``: ``--arg NAME=VALUE`` items."""
    pieces, values = compose(text, source, parse_args(args or []))
    top = pieces[0]
    report = Report(source, raw_names(top.data), override=False)
    report.sources = top.sources
    plan = validate(top.data, source, report, included=pieces[1:])
    return msgspec.structs.replace(plan, args=values)


def load_launch(path: Path, args: list[str] | None = None) -> LaunchPlan:
    """Read and validate a launch file from disk (``args``: ``--arg NAME=VALUE`` items)."""
    return parse_launch(read_text(path, str(path)), source=str(path), args=args)


def default_launch_file() -> Path:
    """./launch.toml if there is one, else the packaged default."""
    local = Path("launch.toml")
    return local if local.is_file() else PACKAGED_LAUNCH
