"""Who may reach the page (its origin, its host name), the files it serves, and teleop's deadman."""

from __future__ import annotations

from http import HTTPStatus

import pytest

from turtlectl.cli.web.actions import Deadman
from turtlectl.cli.web.server import _file, allowed, is_loopback


@pytest.mark.parametrize(
    ("origin", "host", "loopback_only", "refused"),
    [
        ("http://127.0.0.1:8080", "127.0.0.1:8080", True, ""),
        ("http://localhost:8080", "localhost:8080", True, ""),
        (None, "127.0.0.1:8080", True, ""),  # not a browser's: no origin to check
        ("http://evil.example", "127.0.0.1:8080", True, "origin 'http://evil.example' is not this page's"),
        ("http://127.0.0.1:9999", "127.0.0.1:8080", True, "is not this page's"),
        # a page elsewhere whose name now points at 127.0.0.1 (DNS rebinding): same origin, wrong host
        ("http://evil.example:8080", "evil.example:8080", True, "host 'evil.example:8080' is not this server's"),
        ("http://robot.local:8080", "robot.local:8080", False, ""),  # listening beyond loopback: any name
        ("http://evil.example", "robot.local:8080", False, "is not this page's"),
        ("http://127.0.0.1:8080", None, True, "no Host header"),
    ],
)
def test_who_may_connect(origin: str | None, host: str | None, loopback_only: bool, refused: str) -> None:
    why = allowed(origin, host, loopback_only)
    assert (refused in why) if refused else why == ""
    if refused:
        assert why


def test_loopback_addresses() -> None:
    assert is_loopback("127.0.0.1") and is_loopback("localhost") and is_loopback("::1") and is_loopback("127.3.0.1")
    assert not is_loopback("0.0.0.0") and not is_loopback("192.168.1.4") and not is_loopback("robot.local")


def test_the_page_files_and_nothing_else() -> None:
    index = _file("/")
    assert index.status_code == HTTPStatus.OK
    assert b"app.js" in index.body
    assert index.headers["Content-Type"].startswith("text/html")
    assert "default-src 'self'" in index.headers["Content-Security-Policy"]
    assert _file("/app.js").headers["Content-Type"].startswith("text/javascript")
    for outside in ("/../protocol.py", "/../../../pyproject.toml", "/missing.js", "/%2e%2e/server.py"):
        assert _file(outside).status_code == HTTPStatus.NOT_FOUND


def test_the_page_fetches_nothing_from_elsewhere() -> None:
    from turtlectl.cli.web.server import STATIC

    for path in STATIC.iterdir():
        text = path.read_text()
        assert "http://" not in text and "https://" not in text and "//cdn" not in text, path.name


def test_the_deadman_stops_a_turtle_whose_commands_stop() -> None:
    deadman = Deadman(limit=0.5)
    assert deadman.drive("turtle1", 10.0) is True  # it starts driving: a running goal is canceled
    assert deadman.drive("turtle1", 10.1) is False
    assert deadman.due(10.5) == []
    assert deadman.due(10.6) == ["turtle1"]
    assert deadman.due(11.0) == []  # stopped once, not again


def test_a_stop_and_a_page_that_goes_away() -> None:
    deadman = Deadman(limit=0.5)
    deadman.drive("turtle1", 0.0)
    assert deadman.stop("turtle1") is True
    assert deadman.stop("turtle1") is False
    deadman.drive("turtle1", 1.0)
    deadman.drive("turtle2", 1.0)
    assert sorted(deadman.all()) == ["turtle1", "turtle2"]
    assert deadman.due(99.0) == []
