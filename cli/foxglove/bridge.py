"""``turtlectl foxglove``: the running system served to the Foxglove app over its WebSocket
protocol (the foxglove-sdk's server).  Nothing here prints.

* Every topic of the live graph is a channel of the same name, its messages JSON with the
  type's JSON Schema (messages.jsonform), appearing and disappearing with the graph (checked
  every ``GRAPH_PERIOD`` s).  A user's own type is learnt from the nodes that use it
  (runtime.client.typebook) and served as a built-in is; a type no node describes is not served.
* The ready-made scene (cli.foxglove.scene): ``scene`` and ``scene/scan`` in Foxglove's well-known (protobuf)
  schemas, so the 3D panel shows the world, every turtle (named) with its trail and goal, and the scan;
  and ``log``, every node's log records (``turtlectl/log/<node>``) as Foxglove's Log, for its Log panel.
* ``navigate_to``, ``navigate_to/cancel``, ``reset`` and ``turtle1/teleport_absolute`` are
  Foxglove services (JSON requests as for ``turtlectl call``): a goal can be sent from the app.

Samples are taken on Zenoh's threads and queued; the caller's thread logs them to the server.
"""

from __future__ import annotations

import json
import queue
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import foxglove
import zenoh
from foxglove import Channel, Schema
from foxglove.channels import LaserScanChannel, LogChannel, SceneUpdateChannel
from foxglove.websocket import Capability, MessageSchema, ServerListener, Service, ServiceRequest, ServiceSchema

from turtlectl.cli.foxglove.scene import LOG, SCAN, SCENE, SceneMaker
from turtlectl.messages import (
    Ack,
    Cancel,
    ErrorReply,
    Message,
    NavigateToRequest,
    NavigateToResponse,
    Reset,
    TeleportAbsolute,
    decode,
    decode_any,
    encode,
    encoding_for,
    type_from_encoding,
)
from turtlectl.messages.codec import TYPES_BY_NAME, DecodeError, type_name
from turtlectl.messages.described import describable
from turtlectl.messages.jsonform import JsonFormError, from_json, json_schema, to_json
from turtlectl.messages.keys import CANCEL, NAVIGATE_TO, RESET, TELEPORT
from turtlectl.runtime.client.errors import Failed
from turtlectl.runtime.client.services import world as world_of
from turtlectl.runtime.client.session import client_session, live_graph, logged_in_as
from turtlectl.runtime.client.typebook import TypeBook

GRAPH_PERIOD = 1.0  # s between two looks at the live graph (channels come and go)
WORLD_PERIOD = 1.0  # s between two sendings of the world (a viewer may connect at any time)
GOAL_TIMEOUT = 600.0  # s the navigate_to service waits for the goal's outcome


def _schema(msg_type: type[Message]) -> Schema:
    return Schema(name=type_name(msg_type), encoding="jsonschema", data=json.dumps(json_schema(msg_type)).encode())


def _message_schema(msg_type: type[Message]) -> MessageSchema:
    return MessageSchema(encoding="json", schema=_schema(msg_type))


#: the services offered to Foxglove: key -> (request type, response type, query every server)
SERVICES: dict[str, tuple[type[Message], type[Message], bool]] = {
    NAVIGATE_TO: (NavigateToRequest, NavigateToResponse, False),
    CANCEL: (Cancel, Ack, False),
    RESET: (Reset, Ack, True),
    TELEPORT: (TeleportAbsolute, Ack, False),
}


def _call(session: zenoh.Session, key: str, request: Message, everyone: bool, response_type: type[Message]) -> bytes:
    """Call ``key`` with ``request``; the JSON of the answer (the last one of ``response_type``:
    a goal's feedback is skipped; with ``everyone``, a JSON array of every server's answer).
    Raises RuntimeError with the reason, which Foxglove shows as the call's failure."""
    replies = session.get(
        key,
        payload=encode(request),
        encoding=zenoh.Encoding(encoding_for(type(request))),
        consolidation=zenoh.ConsolidationMode.NONE,
        target=zenoh.QueryTarget.ALL if everyone else zenoh.QueryTarget.BEST_MATCHING,
        timeout=GOAL_TIMEOUT if key == NAVIGATE_TO else 5.0,
    )
    answers: list[Message] = []
    for reply in replies:
        if reply.err is not None:
            try:
                raise RuntimeError(decode(reply.err.payload.to_bytes(), ErrorReply).error)
            except DecodeError:
                raise RuntimeError(f"{key} answered with an error") from None
        try:
            message = decode_any(reply.ok.payload.to_bytes())
        except DecodeError:
            continue
        if isinstance(message, response_type):
            answers.append(message)
    if not answers:
        raise RuntimeError(f"nothing answered {key} (is the system running?)")
    if everyone:
        return b"[" + b",".join(to_json(a) for a in answers) + b"]"
    return to_json(answers[-1])


def _services(session: zenoh.Session) -> list[Service]:
    services = []
    for key, (request_type, response_type, everyone) in SERVICES.items():

        def handler(
            request: ServiceRequest,
            key: str = key,
            request_type=request_type,
            response_type=response_type,
            everyone=everyone,
        ) -> bytes:
            payload = request.payload or b"{}"
            try:
                body = from_json(payload, request_type)
            except JsonFormError as exc:
                raise ValueError(str(exc)) from None
            return _call(session, key, body, everyone, response_type)

        response = _message_schema(response_type)
        if everyone:
            array = {"type": "array", "items": json_schema(response_type), "title": f"{type_name(response_type)}[]"}
            response = MessageSchema(
                encoding="json",
                schema=Schema(name=array["title"], encoding="jsonschema", data=json.dumps(array).encode()),
            )
        schema = ServiceSchema(type_name(request_type), request=_message_schema(request_type), response=response)
        services.append(Service(key, schema=schema, handler=handler))
    return services


class Bridge(ServerListener):
    """The channels of one server: the graph's topics (JSON) and the scene.  Its server's
    listener: the SDK calls every listener method (the others are ServerListener's no-ops)."""

    def __init__(self, session: zenoh.Session):
        self.session = session
        self.book = TypeBook(session)  # the user's own types, learnt from the nodes (refresh's thread)
        self.channels: dict[str, Channel] = {}  # key -> its JSON channel
        self.scene = SceneUpdateChannel(SCENE)
        self.scan = LaserScanChannel(SCAN)
        self.log = LogChannel(LOG)
        self.drawn = {SCENE: self.scene, SCAN: self.scan, LOG: self.log}  # SceneMaker's topics -> their channels
        self.maker = SceneMaker(world_of(session))
        self.inbox: queue.SimpleQueue[tuple[str, str, bytes, int]] = queue.SimpleQueue()
        self.world_wanted = threading.Event()  # a viewer subscribed to the scene: draw the world now

    def on_subscribe(self, _client: Any, channel: Any) -> None:  # the server's thread: flag only
        if channel.topic == SCENE:
            self.world_wanted.set()

    def refresh(self) -> None:
        """Channels for the topics the graph has now (a publisher and a known type), and none
        for those it no longer has."""
        live = [t for t in live_graph(self.session).topics if t.publishers]
        topics = {t.key: t.type for t in live if t.type in TYPES_BY_NAME or self._learnt(t.type)}
        for key in [k for k in self.channels if k not in topics]:
            self.channels.pop(key).close()
        for key, name in topics.items():
            if key not in self.channels:
                self.channels[key] = Channel(key, schema=_schema(TYPES_BY_NAME[name]), message_encoding="json")

    def _learnt(self, name: str) -> bool:
        """A type turtlectl was not built with, now learnt from the nodes that use it."""
        return describable(name) and self.book.resolve(name) is not None

    def on_sample(self, sample: zenoh.Sample) -> None:  # Zenoh thread: take and queue only
        self.inbox.put((str(sample.key_expr), str(sample.encoding), sample.payload.to_bytes(), time.time_ns()))

    def forward(self, key: str, encoding: str, payload: bytes, received: int) -> None:
        msg_type = type_from_encoding(encoding)
        if msg_type is None:
            return
        try:
            message = decode(payload, msg_type)
        except DecodeError:
            return
        channel = self.channels.get(key)
        if channel is not None and channel.has_sinks():  # JSON only for a viewer subscribed to it
            channel.log(to_json(message), log_time=received)
        for topic, drawn in self.maker.on_message(key, message, received):
            self.drawn[topic].log(drawn, log_time=received)

    def send_world(self) -> None:
        now = time.time_ns()
        _, drawn = self.maker.world_update(now)
        self.scene.log(drawn, log_time=now)

    def close(self) -> None:
        for channel in [*self.channels.values(), *self.drawn.values()]:
            channel.close()
        self.channels.clear()


def serve(
    connect: str,
    domain: str,
    host: str,
    port: int,
    stop: threading.Event,
    started: Callable[[Any], None] = lambda _s: None,
) -> Iterator[int]:
    """Serve the system at ``connect`` on ws://``host``:``port`` until ``stop`` is set; calls
    ``started(server)`` once it listens, then yields the number of channels each second."""
    with client_session(connect, domain) as session:
        if logged_in_as(session) not in (None, "viewer"):
            raise Failed(
                f"foxglove serves what its role may to anyone who reaches its WebSocket, without a login: on a "
                f"--secure system run it as a viewer (TURTLECTL_ROLE=viewer), not as {logged_in_as(session)}"
            )
        bridge = Bridge(session)
        try:
            server = foxglove.start_server(
                name="turtlectl",
                host=host,
                port=port,
                capabilities=[Capability.Services],
                supported_encodings=["json"],
                services=_services(session),
                server_listener=bridge,
            )
        except RuntimeError as exc:
            bridge.close()
            from turtlectl.runtime.client.errors import CannotStart

            raise CannotStart(f"cannot serve Foxglove on {host}:{port}: {exc}") from None
        sub = session.declare_subscriber("**", bridge.on_sample)
        try:
            started(server)
            next_graph = next_world = time.monotonic()
            while not stop.is_set():
                now = time.monotonic()
                if now >= next_graph:
                    next_graph = now + GRAPH_PERIOD
                    bridge.refresh()
                    yield len(bridge.channels)
                if now >= next_world or bridge.world_wanted.is_set():
                    bridge.world_wanted.clear()
                    next_world = now + WORLD_PERIOD
                    bridge.send_world()
                try:
                    bridge.forward(*bridge.inbox.get(timeout=0.05))
                except queue.Empty:
                    pass
        finally:
            sub.undeclare()
            bridge.close()
            server.stop()
