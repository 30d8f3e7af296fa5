"""This checkout against another (the code before a change), alternated in one run, on the figures a
refactoring must not make worse: launch-to-ready, ``turtlectl --help``, the whole system's idle
CPU and memory, and robot/status's one-way latency.  Optionally a third variant, this checkout
with every node exec'd instead of forked from the zygote (``--no-zygote``), which weighs what the
zygote buys.

Each variant runs its own ``.venv/bin/turtlectl`` from its own folder as a black box: started on a
free port, ready when its four nodes hold their liveliness tokens (watched from a session of this
process), measured, stopped with SIGINT to its process group.  Prints medians and percentiles per
variant and the ratio of medians against "before": machines here are shared and noisy, compare
ratios.

Usage: python bench/system.py --before ../before [--rounds 6] [--no-zygote]
(``--before``: a checkout of the code before, e.g. ``git worktree add ../before HEAD~5`` then
``make bytecode`` there.)
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import psutil
import zenoh

from bench.startup import free_port, help_time, launched
from bench.system import machine, pct, summary
from turtlectl.messages import TurtleStatus, decode
from turtlectl.messages.keys import STATUS

IDLE_WINDOW = 5.0  # s: CPU is measured over this long, once the system is ready and settled
SETTLE = 1.0  # s: after readiness, before measuring (the nodes' first ticks and subscriptions)
LATENCY_SAMPLES = 50  # robot/status samples per round (10 Hz: 5 s)

# the launch with the zygote's start switched off, so every node starts by exec (the fallback a
# launch takes when the zygote cannot fork a node)
NO_ZYGOTE = (
    "import sys; from turtlectl.cli.system.supervisor import zygote; zygote.start = lambda: None; "
    "sys.argv = ['turtlectl', *sys.argv[1:]]; from turtlectl.cli import entry; entry()"
)


@dataclass
class Variant:
    name: str
    checkout: Path
    zygote: bool = True
    ready: list[float] = field(default_factory=list)  # s
    helps: list[float] = field(default_factory=list)  # s
    cpu: list[float] = field(default_factory=list)  # % of one core, whole system
    pss: list[float] = field(default_factory=list)  # MiB, whole system
    latency: list[float] = field(default_factory=list)  # s, robot/status stamp to arrival here

    def argv(self, port: int) -> list[str]:
        bin_dir = self.checkout / ".venv" / "bin"
        if self.zygote:
            return [str(bin_dir / "turtlectl"), "launch", "--port", str(port)]
        return [str(bin_dir / "python"), "-c", NO_ZYGOTE, "launch", "--port", str(port)]


def tree(root: int) -> list[psutil.Process]:
    try:
        proc = psutil.Process(root)
        return [proc, *proc.children(recursive=True)]
    except psutil.NoSuchProcess:
        return []


def cpu_of(procs: list[psutil.Process], seconds: float) -> float:
    """% of one core the processes used together over ``seconds``."""

    def total() -> float:
        used = 0.0
        for p in procs:
            try:
                t = p.cpu_times()
                used += t.user + t.system
            except psutil.NoSuchProcess:
                pass
        return used

    before, started = total(), time.monotonic()
    time.sleep(seconds)  # the measurement window
    return 100.0 * (total() - before) / (time.monotonic() - started)


def pss_of(procs: list[psutil.Process]) -> float:
    used = 0.0
    for p in procs:
        try:
            used += p.memory_full_info().pss
        except (psutil.NoSuchProcess, psutil.AccessDenied):
            pass
    return used / 2**20


def one_round(variant: Variant, timeout: float = 30.0) -> None:
    """Launch ``variant``, time it to ready, measure it idle, stop it."""
    arrivals: list[float] = []
    enough = threading.Event()

    def on_status(sample: zenoh.Sample) -> None:
        now_ns = time.time_ns()
        arrivals.append((now_ns - decode(sample.payload.to_bytes(), TurtleStatus).stamp) / 1e9)
        if len(arrivals) >= LATENCY_SAMPLES:
            enough.set()

    port = free_port()
    with launched(variant.argv(port), variant.checkout, port, timeout) as ready:
        variant.ready.append(ready.seconds)
        time.sleep(SETTLE)  # pacing: the system settles before it is measured idle
        procs = tree(ready.pid)
        variant.cpu.append(cpu_of(procs, IDLE_WINDOW))
        variant.pss.append(pss_of(procs))
        status = ready.session.declare_subscriber(STATUS, on_status)
        if not enough.wait(LATENCY_SAMPLES / 10 + 10):
            raise RuntimeError(f"{variant.name}: {len(arrivals)} robot/status samples")
        status.undeclare()
        variant.latency.extend(arrivals[:LATENCY_SAMPLES])


def compare(this: Path, before: Path, rounds: int, helps: int, no_zygote: bool) -> None:
    variants = [Variant("this", this), Variant("before", before)]
    if no_zygote:
        variants.append(Variant("this, exec'd", this, zygote=False))
    print(f"machine: {machine()}")
    for _ in range(rounds):
        for variant in variants:  # alternated: the machine's noise falls on each
            one_round(variant)
    for _ in range(helps):
        for variant in variants[:2]:
            variant.helps.append(help_time(variant.checkout))
    base = variants[1]
    figures = (
        ("launch-to-ready", "ready", "ms", 1e3),
        ("--help", "helps", "ms", 1e3),
        ("idle CPU, whole system", "cpu", "%", 1.0),
        ("PSS, whole system", "pss", "MiB", 1.0),
        ("robot/status latency", "latency", "ms", 1e3),
    )
    for title, attr, unit, scale in figures:
        for variant in variants:
            values = getattr(variant, attr)
            if values:
                print(f"{title} {variant.name:>12}: {summary(values, unit, scale)}")
        for variant in variants:
            values, before_values = getattr(variant, attr), getattr(base, attr)
            if variant is not base and values:
                ratio = pct(values, 50) / pct(before_values, 50)
                print(f"{title}: ratio of medians {variant.name}/before {ratio:.3f}")
