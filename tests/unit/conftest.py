"""Every unit test leaves the process's signal handlers as it found them: a command run
in-process (CliRunner) that kept its SIGTERM handler made the whole test run deaf to
SIGTERM, so `timeout` could not end a hung run.  And the environment variables the root
options set (``--domain``, ``--connect``): a test's ``--domain a/b`` run in-process stayed in
os.environ for every later test of that worker (monkeypatch.delenv of an absent variable
restores nothing)."""

from __future__ import annotations

import os
import signal

import pytest


@pytest.fixture(autouse=True)
def signal_handlers_restored():
    before = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    yield
    after = {sig: signal.getsignal(sig) for sig in before}
    for sig, handler in before.items():
        signal.signal(sig, handler)  # put back, so one leak fails one test, not every later one
    changed = [sig.name for sig in before if after[sig] is not before[sig]]
    assert not changed, f"the test left its own handler for {', '.join(changed)}"


@pytest.fixture(autouse=True)
def root_option_environment_restored():
    names = ("TURTLECTL_DOMAIN", "TURTLECTL_CONNECT")
    before = {name: os.environ.get(name) for name in names}
    yield
    for name, value in before.items():
        if value is None:
            os.environ.pop(name, None)
        else:
            os.environ[name] = value
