"""The page's server: HTTP for the page's files (``static/``, shipped in the package: no build step,
nothing fetched from elsewhere) and its WebSocket, ``/ws``, on one port (the ``websockets``
library's asyncio server, on a thread of its own).

Each page gets ``hello``, then a sender task that sends what changed (hub.Hub.changes) whenever
the hub wakes it: a frame is built from the newest state as the previous one has gone out, so a
slow page gets fewer frames, never older ones.  Its frames in are parsed (protocol.parse), checked
against the role (protocol.refusal) and done (actions.Actions); a bad frame gets one ``error``.

Who may connect: the page's own origin only.  A WebSocket whose ``Origin`` is not this server
(``http://`` + the ``Host`` it asked for) is refused (403), and so is a request whose ``Host``
is not a loopback name while the server listens on loopback only (a web page elsewhere that
renamed itself to 127.0.0.1: DNS rebinding).
"""

from __future__ import annotations

import asyncio
import contextlib
import ipaddress
import logging
import mimetypes
import threading
import time
from collections.abc import Callable
from http import HTTPStatus
from pathlib import Path
from typing import Any

from websockets.asyncio.server import Server, ServerConnection, serve
from websockets.datastructures import Headers
from websockets.exceptions import ConnectionClosed
from websockets.http11 import Request, Response

from turtlectl.cli.web import protocol
from turtlectl.cli.web.actions import Actions, Deadman
from turtlectl.cli.web.hub import Hub
from turtlectl.runtime.client.session import ROUTER_CHECK

STATIC = Path(__file__).with_name("static")
# the library's own line per connection opened and closed would fill the node's log: the page's own say who
logging.getLogger("websockets").setLevel(logging.WARNING)
LOOPBACK_NAMES = {"localhost", "127.0.0.1", "[::1]", "::1"}
GRAPH_PERIOD = 1.0  # s between two graph frames
TICK = 0.05  # s: how often the deadman and the router are looked at
FRAME_PERIOD = 0.016  # s: the simulator's step; a page gets at most a frame per step


def is_loopback(host: str) -> bool:
    """True if the address ``host`` is a loopback one (127.0.0.0/8, ::1, localhost)."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def allowed(origin: str | None, host: str | None, loopback_only: bool) -> str:
    """Why a request with headers ``Origin`` and ``Host`` is refused ("" if it is not): another
    origin's WebSocket, or a host name not this server's while it listens on loopback only.
    A request with no Origin (not a browser's) passes the origin check."""
    if host is None:
        return "no Host header"
    name = host.rsplit(":", 1)[0] if not host.endswith("]") else host
    if loopback_only and name not in LOOPBACK_NAMES:
        return f"host {host!r} is not this server's (it listens on loopback only)"
    if origin is not None and origin != f"http://{host}":
        return f"origin {origin!r} is not this page's (http://{host})"
    return ""


class Page:
    """One connected page: what it watches, what it drives, what it was last sent."""

    def __init__(self, connection: ServerConnection):
        self.connection = connection
        self.sent = 0  # the hub version of the last frame sent
        self.logs_sent = 0
        self.echo_sent = 0
        self.watched: set[str] = set()
        self.deadman = Deadman()
        self.outbox: asyncio.Queue[bytes] = asyncio.Queue()
        self.wake = asyncio.Event()


class WebServer:
    """Serves pages of the system ``actions.client`` reaches; ``start`` binds (OSError if the port
    is taken), ``stop`` closes every page and the port."""

    def __init__(
        self,
        host: str,
        port: int,
        actions: Actions,
        hub_of: Callable[[Callable[[], None]], Hub],
        hello: dict[str, Any],
        role: str,
        log: logging.Logger,
        graph_frame: Callable[[], bytes | None],
        router_check: Callable[[], bool],
    ):
        """``hub_of(wake)``: the hub, given how it wakes the pages; ``hello``: the first frame's
        fields (``can`` among them: what a page may do); ``graph_frame``: the ``graph`` frame now
        (None: none to send); ``router_check``: True while the router is lost.  The last two block:
        they run on a worker thread."""
        self.host, self.port = host, port
        self.actions = actions
        self.hello = hello
        self.can: protocol.Can = hello["can"]
        self.graph_frame = graph_frame
        self.role = role
        self.log = log
        self.loop = asyncio.new_event_loop()
        self.pages: set[Page] = set()
        self.hub = hub_of(self._wake_all)
        self._server: Server | None = None
        self._thread: threading.Thread | None = None
        self._ready = threading.Event()
        self._error: BaseException | None = None
        self.router_lost = False
        self.router_check = router_check

    # lifecycle -------------------------------------------------------------------------------------

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="web server", daemon=True)
        self._thread.start()
        self._ready.wait(10.0)
        if self._error is not None:
            raise self._error

    def _run(self) -> None:
        asyncio.set_event_loop(self.loop)
        try:
            self._server = self.loop.run_until_complete(self._open())
        except BaseException as exc:
            self._error = exc
            self._ready.set()
            return
        self._ready.set()
        self.loop.create_task(self._ticks())
        self.loop.run_forever()

    async def _open(self) -> Server:
        return await serve(
            self._page,
            self.host,
            self.port,
            process_request=self._http,
            max_size=protocol.MAX_FRAME,
            ping_interval=5,
            ping_timeout=5,
            compression=None,
        )

    def stop(self) -> None:
        """Stop every turtle a page drives, close the pages and the port (bounded)."""
        if self._server is None:
            return

        async def close() -> None:
            for page in list(self.pages):
                self._stop_driving(page)
            assert self._server is not None
            self._server.close()
            with contextlib.suppress(asyncio.TimeoutError):
                await asyncio.wait_for(self._server.wait_closed(), 2.0)

        async def end_tasks() -> None:  # the ticks and the pages' senders end here, not destroyed pending
            tasks = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)

        with contextlib.suppress(Exception):
            asyncio.run_coroutine_threadsafe(close(), self.loop).result(3.0)
        with contextlib.suppress(Exception):
            asyncio.run_coroutine_threadsafe(end_tasks(), self.loop).result(3.0)
        self.loop.call_soon_threadsafe(self.loop.stop)
        if self._thread is not None:
            self._thread.join(3.0)

    # HTTP ------------------------------------------------------------------------------------------

    def _http(self, connection: ServerConnection, request: Request) -> Response | None:
        why = allowed(request.headers.get("Origin"), request.headers.get("Host"), is_loopback(self.host))
        if why:
            self.log.warning("refused a request for %s: %s", request.path, why)
            return connection.respond(HTTPStatus.FORBIDDEN, f"refused: {why}\n")
        path = request.path.partition("?")[0]
        if path == protocol.PATH:
            return None  # the WebSocket handshake goes on
        return _file(path)

    # a page ----------------------------------------------------------------------------------------

    async def _page(self, connection: ServerConnection) -> None:
        page = Page(connection)
        self.pages.add(page)
        self.hub.viewed = True
        peer = connection.remote_address
        self.log.info("a page connected from %s:%s (%d open)", peer[0], peer[1], len(self.pages))
        sender = asyncio.create_task(self._sender(page))
        try:
            await connection.send(protocol.encode("hello", **self.hello, router_lost=self.router_lost).decode())
            async for data in connection:
                self._take(page, data)
        except ConnectionClosed:
            pass
        finally:
            sender.cancel()
            self._stop_driving(page)
            self.hub.watch(set(), page.watched)
            self.pages.discard(page)
            self.hub.viewed = bool(self.pages)
            self.log.info("a page from %s:%s went away (%d open)", peer[0], peer[1], len(self.pages))

    def _take(self, page: Page, data: str | bytes) -> None:
        try:
            frame = protocol.parse(data)
        except protocol.BadFrame as exc:
            self.log.warning("a page sent a frame it may not: %s", exc)
            page.outbox.put_nowait(protocol.encode("error", text=str(exc)))
            page.wake.set()
            return
        refused = protocol.refusal(self.role, frame, self.can)
        if refused:
            if isinstance(frame, protocol.Asked):
                page.outbox.put_nowait(protocol.reply(frame, False, refused))
            else:
                page.outbox.put_nowait(protocol.encode("error", text=refused))
            page.wake.set()
            return
        if isinstance(frame, protocol.Watch):
            keys = set(frame.keys)
            self.hub.watch(keys - page.watched, page.watched - keys)
            page.watched = keys
            return
        if isinstance(frame, protocol.Drive):
            if self.router_lost:
                return  # nothing is sent while the router is lost: it would drive on stale keys later
            if page.deadman.drive(frame.turtle, time.monotonic()):
                self.actions.take_over(frame.turtle)
        elif isinstance(frame, protocol.Stop):
            page.deadman.stop(frame.turtle)
        self.actions.handle(frame, lambda out: self._send_to(page, out))

    def _send_to(self, page: Page, frame: bytes) -> None:
        """``frame`` to ``page``, from any thread."""

        def put() -> None:
            page.outbox.put_nowait(frame)
            page.wake.set()

        self.loop.call_soon_threadsafe(put)

    def broadcast(self, frame: bytes) -> None:
        """``frame`` to every page, from any thread."""
        for page in list(self.pages):
            self._send_to(page, frame)

    def _wake_all(self) -> None:
        """The hub has news (Zenoh's thread): every page's sender looks."""
        self.loop.call_soon_threadsafe(self._set_all)

    def _set_all(self) -> None:
        for page in self.pages:
            page.wake.set()

    async def _sender(self, page: Page) -> None:
        connection = page.connection
        last = 0.0
        while True:
            await page.wake.wait()
            # at most a frame per simulator step: what arrives meanwhile (another turtle's pose) joins it
            await asyncio.sleep(max(0.0, last + FRAME_PERIOD - time.monotonic()))
            last = time.monotonic()
            page.wake.clear()
            while not page.outbox.empty():
                await connection.send(page.outbox.get_nowait().decode())
            page.sent, changed = self.hub.changes(page.sent)
            if changed:
                await connection.send(protocol.encode("frame", **changed, sent=time.time() * 1000.0).decode())
            page.logs_sent, logs = self.hub.logs(page.logs_sent)
            if logs:
                await connection.send(protocol.encode("log", records=logs).decode())
            if page.watched:
                page.echo_sent, echoes = self.hub.echoes(page.watched, page.echo_sent)
                for echo in echoes[-protocol.WATCH_LIMIT * 4 :]:
                    await connection.send(protocol.encode("echo", **echo).decode())

    def _stop_driving(self, page: Page) -> None:
        for turtle in page.deadman.all():
            self._stop(turtle)

    def _stop(self, turtle: str) -> None:
        try:
            self.actions.drive(turtle, 0.0, 0.0)
        except Exception as exc:  # the router gone: the simulator's own cmd_vel timeout stops it
            self.log.warning("could not stop %s: %s", turtle, exc)

    async def _ticks(self) -> None:
        """The deadman of every page, the router's presence and the graph, on the server's loop."""
        next_graph = next_router = 0.0
        while True:
            now = time.monotonic()
            for page in list(self.pages):
                for turtle in page.deadman.due(now):
                    self.log.info("%s stopped: its page sent no drive command for %.1f s", turtle, page.deadman.limit)
                    self._stop(turtle)
            lost = self.router_lost
            if now >= next_router:  # as often as every long-running tool looks (runtime.client.session)
                next_router = now + ROUTER_CHECK
                lost = await self.loop.run_in_executor(None, self.router_check)
            if lost != self.router_lost:
                self.router_lost = lost
                self.log.warning("router %s", "lost: waiting for it to come back" if lost else "back")
                self.broadcast(
                    protocol.encode("router", state="lost" if lost else "back", connect=self.actions.client.connect)
                )
                if lost:
                    for page in list(self.pages):
                        page.deadman.all()
            if now >= next_graph and self.pages:
                next_graph = now + GRAPH_PERIOD
                graph = await self.loop.run_in_executor(None, self.graph_frame)
                if graph is not None:
                    self.broadcast(graph)
            await asyncio.sleep(TICK)


def _file(path: str) -> Response:
    """One of the page's files (``/`` is index.html), or 404."""
    name = "index.html" if path in ("", "/") else path.lstrip("/")
    target = (STATIC / name).resolve()
    if STATIC.resolve() not in target.parents or not target.is_file():
        return Response(HTTPStatus.NOT_FOUND, "Not Found", Headers([("Content-Type", "text/plain")]), b"not found\n")
    kind = mimetypes.guess_type(target.name)[0] or "application/octet-stream"
    if kind.startswith("text/") or kind.endswith("javascript"):
        kind += "; charset=utf-8"
    body = target.read_bytes()
    headers = Headers(
        [
            ("Content-Type", kind),
            ("Content-Length", str(len(body))),
            ("Cache-Control", "no-cache"),
            # the page runs only its own scripts, and talks only to this server
            ("Content-Security-Policy", "default-src 'self'; connect-src 'self'; img-src 'self' data:"),
            ("X-Content-Type-Options", "nosniff"),
        ]
    )
    return Response(HTTPStatus.OK, "OK", headers, body)
