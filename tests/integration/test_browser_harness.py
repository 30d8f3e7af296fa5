"""The browser tests' harness (tests/integration/browser.py) on a page of its own: a real Chromium
loads it from a server on 127.0.0.1, the page's model is read and changed by a click and a key, a
screenshot is a PNG of the viewport's size, the page's errors are collected, a wait that never comes
true fails with what it saw, and the browser's processes are gone after the block."""

from __future__ import annotations

import struct
import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import psutil
import pytest

from tests.integration.browser import browser_page, chromium_path, page_errors, still_running, wait_for

pytestmark = pytest.mark.integration

PAGES = {
    "/": """<!doctype html>
<html><head><meta charset="utf-8"><link rel="icon" href="data:,"><title>harness</title></head>
<body>
<button id="go">go</button>
<script>
window.model = {ready: true, clicks: 0, keys: []};
document.getElementById("go").addEventListener("click", () => { window.model.clicks += 1; });
document.addEventListener("keydown", (event) => { window.model.keys.push(event.key); });
</script>
</body></html>
""",
    "/broken": """<!doctype html>
<html><head><meta charset="utf-8"><link rel="icon" href="data:,"><title>broken</title></head>
<body>
<script>
console.error("drawn nothing");
setTimeout(() => { undefinedFunction(); }, 0);
// a later task than the error's: once the test sees it, Playwright has delivered the error (in order)
setTimeout(() => { window.model = {ready: true}; }, 0);
</script>
</body></html>
""",
}


class Pages(BaseHTTPRequestHandler):
    def do_GET(self) -> None:  # noqa: N802 (http.server's name)
        body = PAGES.get(self.path)
        if body is None:
            self.send_error(404)
            return
        data = body.encode()
        self.send_response(200)
        self.send_header("Content-Type", "text/html; charset=utf-8")
        self.send_header("Content-Length", str(len(data)))
        self.end_headers()
        self.wfile.write(data)

    def log_message(self, format: str, *args) -> None:  # the test's output stays the test's
        pass


@pytest.fixture(scope="module")
def server() -> Iterator[str]:
    """The pages on 127.0.0.1, on a port the kernel picks (free by construction)."""
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), Pages)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}"
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join()


def png_size(data: bytes) -> tuple[int, int]:
    assert data[:8] == b"\x89PNG\r\n\x1a\n", data[:8]
    assert data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def test_a_page_is_read_driven_and_photographed(server, tmp_path):
    with browser_page(server + "/", viewport=(640, 480)) as page:
        assert wait_for(page, "window.model && window.model.ready", 10) is True
        page.click("#go")
        page.mouse.click(*center(page, "#go"))
        page.keyboard.press("ArrowUp")
        assert wait_for(page, "window.model.clicks === 2 && window.model.keys.length === 1", 5)
        assert page.evaluate("window.model") == {"ready": True, "clicks": 2, "keys": ["ArrowUp"]}
        shot = tmp_path / "page.png"
        page.screenshot(path=str(shot))
        assert png_size(shot.read_bytes()) == (640, 480)
        assert page_errors(page) == []


def center(page, selector: str) -> tuple[float, float]:
    box = page.locator(selector).bounding_box()
    assert box is not None
    return box["x"] + box["width"] / 2, box["y"] + box["height"] / 2


def test_the_pages_errors_are_collected(server):
    with browser_page(server + "/broken") as page:
        wait_for(page, "window.model && window.model.ready", 10)
        errors = page_errors(page)
        assert any(e.startswith("console error: drawn nothing") for e in errors), errors
        assert any(e.startswith("page error:") and "undefinedFunction" in e for e in errors), errors


def test_a_wait_that_never_comes_true_fails_with_the_last_value(server):
    with browser_page(server + "/") as page:
        with pytest.raises(pytest.fail.Exception, match=r"last seen: 0"):
            wait_for(page, "window.model.clicks", 0.3)
        with pytest.raises(pytest.fail.Exception, match=r"last seen: .threw TypeError: .*'here'"):
            wait_for(page, "window.nothing.here", 0.3)


def test_the_browser_is_gone_after_the_block_also_when_it_fails(server):
    before = {p.pid for p in psutil.Process().children(recursive=True)}
    with pytest.raises(RuntimeError, match="the test failed"):
        with browser_page(server + "/") as page:
            started = [p for p in psutil.Process().children(recursive=True) if p.pid not in before]
            assert any("chrom" in p.name().lower() for p in started), [p.name() for p in started]
            wait_for(page, "window.model.ready", 10)
            raise RuntimeError("the test failed")
    assert [p for p in started if still_running(p)] == []


def test_turtlectl_chromium_names_the_browser_and_a_wrong_name_fails_clearly(monkeypatch):
    monkeypatch.setenv("TURTLECTL_CHROMIUM", "/nonexistent/chromium")
    with pytest.raises(pytest.fail.Exception, match="TURTLECTL_CHROMIUM='/nonexistent/chromium' is not an executable"):
        chromium_path()
    monkeypatch.delenv("TURTLECTL_CHROMIUM")
    found = chromium_path()
    monkeypatch.setenv("TURTLECTL_CHROMIUM", found)
    assert chromium_path() == found
