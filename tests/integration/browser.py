"""A real browser for the tests of a page: Debian's Chromium (``make test`` installs it when missing;
``TURTLECTL_CHROMIUM`` names another executable) driven through Playwright's sync API, headless.

Playwright's pip package brings no browser and none is downloaded: ``chromium_path()`` finds the one
on this machine and fails, naming the set-up, when there is none (a skipped browser test would hide
a page that no longer works).

``browser_page(url)`` yields the page once it has loaded; the console's errors and the page's uncaught
exceptions are collected from the start (``page_errors(page)``, a list a test asserts empty; a resource
that fails to load is one, the favicon Chromium asks for included: a page names its own, or ``data:,``), and the
browser with every process it started is gone when the block ends, also when it fails.
``wait_for(page, expression)`` re-evaluates a JavaScript expression under a deadline: the page's
readiness is a value it exposes (``window.model``), never a fixed sleep.
"""

from __future__ import annotations

import os
import shutil
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import psutil
import pytest
from playwright.sync_api import Error as PlaywrightError
from playwright.sync_api import Page, sync_playwright

#: where Debian's package puts it (a script that sets Chromium's flags from /etc/chromium.d, then runs it)
DEBIAN_CHROMIUM = "/usr/bin/chromium"

#: root in CI (Chromium's sandbox refuses root), no GPU, and nothing the browser fetches on its own
#: (updates, sync, first-run pages): a test's traffic is the page's alone
CHROMIUM_FLAGS = (
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
)

#: Playwright's own limit on each action (a click, a navigation): a page that stopped answering fails
#: its test in seconds instead of Playwright's 30
ACTION_TIMEOUT_S = 10.0

#: how long a killed straggler of the browser gets to go
EXIT_GRACE_S = 5.0

_ERRORS: dict[int, list[str]] = {}


def chromium_path() -> str:
    """TURTLECTL_CHROMIUM (a path or a name on PATH), else Debian's, else ``chromium`` on PATH."""
    named = os.environ.get("TURTLECTL_CHROMIUM")
    if named:
        found = shutil.which(named)
        if found is None:
            pytest.fail(f"TURTLECTL_CHROMIUM={named!r} is not an executable: name a Chromium, or unset it")
        return found
    if os.access(DEBIAN_CHROMIUM, os.X_OK):
        return DEBIAN_CHROMIUM
    found = shutil.which("chromium")
    if found is None:
        pytest.fail(
            "the browser tests need Chromium: `make browser` (part of `make test`) installs Debian's "
            "(apt-get install chromium), or set TURTLECTL_CHROMIUM to a Chromium executable"
        )
    return found


def page_errors(page: Page) -> list[str]:
    """The console's errors and the uncaught exceptions of a page from ``browser_page``, oldest first
    (the same list, growing while the page runs)."""
    return _ERRORS[id(page)]


@contextmanager
def browser_page(url: str, viewport: tuple[int, int] = (1280, 800)) -> Iterator[Page]:
    """A headless Chromium on ``url`` (loaded: its ``load`` event), closed with all its processes on exit."""
    executable = chromium_path()
    before = {p.pid for p in psutil.Process().children()}
    errors: list[str] = []
    page: Page | None = None
    playwright = sync_playwright().start()
    # Playwright's driver: the browser and its helpers run below it, processes the test starts do not
    drivers = [p for p in psutil.Process().children() if p.pid not in before]
    try:
        browser = playwright.chromium.launch(executable_path=executable, args=list(CHROMIUM_FLAGS), headless=True)
        page = browser.new_page(viewport={"width": viewport[0], "height": viewport[1]})
        page.set_default_timeout(ACTION_TIMEOUT_S * 1000)
        page.on("console", lambda message: _on_console(errors, message))
        page.on("pageerror", lambda error: errors.append(f"page error: {error}"))
        page.on("crash", lambda _page: errors.append("page crashed"))
        _ERRORS[id(page)] = errors
        page.goto(url)
        yield page
    finally:
        if page is not None:
            _ERRORS.pop(id(page), None)
        # the browser's processes, found before the close orphans any of them
        ours = _descendants(drivers)
        try:
            playwright.stop()  # closes the browser, then the driver
        except Exception:  # either already gone or stuck: the kill below makes sure
            pass
        # stop() waited for the browser's close: what still runs now (zombies aside, which are no one's to
        # kill) would outlive the test
        left = [p for p in ours if still_running(p)]
        for process in left:
            try:
                process.kill()
            except psutil.NoSuchProcess:
                pass
        psutil.wait_procs(left, timeout=EXIT_GRACE_S)


def wait_for(page: Page, expression: str, timeout_s: float = 10.0) -> Any:
    """The value of ``expression`` (JavaScript) as soon as it is truthy, re-evaluated until ``timeout_s``
    passes; then the test fails with the last value seen (or the exception the expression threw)."""
    deadline = time.monotonic() + timeout_s
    last: Any = None
    while True:
        try:
            last = page.evaluate(expression)
        except PlaywrightError as error:  # e.g. window.model not there yet: a value not ready, not a failure
            last = "threw " + error.message.splitlines()[0].removeprefix("Page.evaluate: ")
        else:
            if last:
                return last
        if time.monotonic() > deadline:
            pytest.fail(f"{expression} was not true within {timeout_s} s; last seen: {last!r}")
        # the page's event loop runs meanwhile (Playwright's wait, one animation frame's order)
        page.wait_for_timeout(20)


def _on_console(errors: list[str], message) -> None:
    if message.type == "error":
        where = message.location
        errors.append(f"console error: {message.text} ({where.get('url')}:{where.get('lineNumber')})")


def still_running(process: psutil.Process) -> bool:
    """Alive and not a zombie (a zombie has exited; its parent has not reaped it yet)."""
    try:
        return process.is_running() and process.status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


def _descendants(roots: list[psutil.Process]) -> list[psutil.Process]:
    found = list(roots)
    for root in roots:
        try:
            found.extend(root.children(recursive=True))
        except psutil.NoSuchProcess:
            pass
    return found
