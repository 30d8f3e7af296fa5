"""`turtlectl foxglove` against the real system, through a real WebSocket client speaking the
Foxglove protocol (subprotocol foxglove.sdk.v1): the graph's topics are advertised with their
JSON Schemas and their messages validate against them; the scene holds the launch file's
obstacles; a goal sent through the navigate_to service moves the turtle."""

from __future__ import annotations

import asyncio
import base64
import json
import os
import signal
import struct
import subprocess
from pathlib import Path

import jsonschema
import pytest
from websockets.asyncio.client import connect

from tests.integration.harness import ROOT, free_port, running_system, turtlectl
from tests.protobuf_schemas import protobuf_class
from turtlectl.cli.system.launchfile import load_launch

pytestmark = pytest.mark.integration

SUBPROTOCOL = "foxglove.sdk.v1"
TOPICS = ("turtle1/pose", "robot/status", "obstacles", "scene", "scene/scan")


def _protobuf_class(channel: dict):
    """The message class of a protobuf channel, from the descriptors it advertises (base64)."""
    return protobuf_class(base64.b64decode(channel["schema"]), channel["schemaName"])


class Client:
    """The Foxglove side: advertised channels and services, subscriptions, service calls."""

    def __init__(self, ws):
        self.ws = ws
        self.channels: dict[str, dict] = {}
        self.services: dict[str, dict] = {}
        self.pending: list[bytes] = []

    async def advertised(self, topics: tuple[str, ...], timeout: float = 10.0) -> None:
        async def wait() -> None:
            while not set(topics) <= set(self.channels) or len(self.services) < 4:
                message = await self.ws.recv()
                if isinstance(message, bytes):
                    self.pending.append(message)
                    continue
                op = json.loads(message)
                if op["op"] == "advertise":
                    self.channels.update({c["topic"]: c for c in op["channels"]})
                elif op["op"] == "advertiseServices":
                    self.services.update({s["name"]: s for s in op["services"]})

        await asyncio.wait_for(wait(), timeout)

    async def messages(
        self, topics: tuple[str, ...], per_topic: int, until=lambda got: True, timeout: float = 30.0
    ) -> dict[str, list[bytes]]:
        ids = {i: t for i, t in enumerate(topics, 1)}
        await self.ws.send(
            json.dumps(
                {
                    "op": "subscribe",
                    "subscriptions": [{"id": i, "channelId": self.channels[t]["id"]} for i, t in ids.items()],
                }
            )
        )
        got: dict[str, list[bytes]] = {t: [] for t in topics}

        async def wait() -> None:
            while any(len(v) < per_topic for v in got.values()) or not until(got):
                message = await self.ws.recv()
                if isinstance(message, bytes) and message[0] == 0x01:
                    subscription, _log_time = struct.unpack_from("<IQ", message, 1)
                    if subscription in ids:
                        got[ids[subscription]].append(message[13:])

        await asyncio.wait_for(wait(), timeout)
        return got

    async def call(self, service: str, request: dict, timeout: float = 60.0) -> dict:
        encoding = b"json"
        sid = self.services[service]["id"]
        await self.ws.send(
            bytes([0x02]) + struct.pack("<III", sid, 7, len(encoding)) + encoding + json.dumps(request).encode()
        )

        async def wait() -> dict:
            while True:
                message = await self.ws.recv()
                if isinstance(message, bytes) and message[0] == 0x03:
                    _sid, call, length = struct.unpack_from("<III", message, 1)
                    if call == 7:
                        return json.loads(message[13 + length :])
                elif isinstance(message, bytes) and message[0] == 0x01:
                    self.pending.append(message)  # a subscription's message meanwhile: kept for ``received``
                elif isinstance(message, str) and json.loads(message)["op"] == "serviceCallFailure":
                    raise AssertionError(message)

        return await asyncio.wait_for(wait(), timeout)

    async def received(self, subscription: int, until, timeout: float = 30.0) -> list[bytes]:
        """The messages of ``subscription`` (kept meanwhile, then as they come) until ``until(got)``."""
        got: list[bytes] = []

        def take(message: bytes) -> None:
            if message[0] == 0x01 and struct.unpack_from("<I", message, 1)[0] == subscription:
                got.append(message[13:])

        for message in self.pending:
            take(message)

        async def wait() -> None:
            while not until(got):
                message = await self.ws.recv()
                if isinstance(message, bytes):
                    take(message)

        await asyncio.wait_for(wait(), timeout)
        return got


def _bridge(endpoint: str, port: int) -> subprocess.Popen[str]:
    proc = subprocess.Popen(
        [*turtlectl(), "foxglove", "--port", str(port), "--connect", endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        text=True,
    )
    assert proc.stderr is not None
    line = proc.stderr.readline()  # an event: it says where it serves once it listens
    assert f"serving Foxglove on ws://127.0.0.1:{port}" in line, line + proc.stderr.read()
    return proc


def test_foxglove_sees_the_topics_the_scene_and_sends_a_goal():
    port = free_port()
    world = load_launch(ROOT / "launch.toml").launch.world
    with running_system() as system:
        system.wait_ready()
        bridge = _bridge(system.endpoint, port)
        try:

            async def session() -> tuple[Client, dict[str, list[bytes]], dict, list[bytes]]:
                async with connect(f"ws://127.0.0.1:{port}", subprotocols=[SUBPROTOCOL], max_size=None) as ws:
                    info = json.loads(await ws.recv())
                    assert info["op"] == "serverInfo" and "services" in info["capabilities"]
                    client = Client(ws)
                    await client.advertised((*TOPICS, "log"))
                    scene = _protobuf_class(client.channels["scene"])
                    got = await client.messages(  # until the world is drawn (sent when the scene is subscribed)
                        TOPICS,
                        3,
                        lambda got: any(e.id == "world" for p in got["scene"] for e in scene.FromString(p).entities),
                    )
                    # an unsubscribe is handled (no "Callback failed: AttributeError: 'Bridge' object has no
                    # attribute 'on_unsubscribe'"), and the call after it after it
                    await ws.send(json.dumps({"op": "unsubscribe", "subscriptionIds": [1]}))
                    # the navigator's log records of the goal, on `log` for Foxglove's Log panel
                    log = {"id": 9, "channelId": client.channels["log"]["id"]}
                    await ws.send(json.dumps({"op": "subscribe", "subscriptions": [log]}))
                    response = await client.call("navigate_to", {"x": 8.0, "y": 5.0, "theta": 90.0})
                    entry = _protobuf_class(client.channels["log"])
                    logged = await client.received(
                        9, lambda got: any("goal reached" in entry.FromString(p).message for p in got)
                    )
                    return client, got, response, logged

            client, got, response, logged = asyncio.run(session())
        finally:
            bridge.terminate()
            out, err = bridge.communicate(timeout=10)
        assert bridge.returncode == 0, err
        assert "Traceback" not in err and "Callback failed" not in out + err, out + err

    for topic in ("turtle1/pose", "robot/status", "obstacles"):
        channel = client.channels[topic]
        assert channel["encoding"] == "json" and channel["schemaEncoding"] == "jsonschema"
        schema = json.loads(channel["schema"])
        for payload in got[topic]:
            jsonschema.validate(json.loads(payload), schema)  # each message satisfies its advertised schema
    assert client.channels["robot/status"]["schemaName"] == "turtlectl/TurtleStatus"

    scene_class = _protobuf_class(client.channels["scene"])
    scenes = [scene_class.FromString(p) for p in got["scene"]]
    world_entities = [e for s in scenes for e in s.entities if e.id == "world"]
    assert world_entities, "no world entity in the scene"
    cylinders = {
        (round(c.pose.position.x, 3), round(c.pose.position.y, 3), round(c.size.x / 2, 3))
        for c in world_entities[0].cylinders
    }
    assert cylinders == {(o.x, o.y, o.radius) for o in world.obstacles}
    scan_class = _protobuf_class(client.channels["scene/scan"])
    scan = scan_class.FromString(got["scene/scan"][0])
    assert scan.frame_id == "world" and len(scan.ranges) > 0

    assert response["type"] == "turtlectl/NavigateToResponse" and response["success"] is True, response
    assert abs(response["x"] - 8.0) < 0.05 and abs(response["y"] - 5.0) < 0.05

    assert client.channels["log"]["schemaName"] == "foxglove.Log"
    entries = [_protobuf_class(client.channels["log"]).FromString(p) for p in logged]
    reached = next(e for e in entries if "goal reached" in e.message)
    assert reached.name == "navigator" and reached.level == 2 and reached.file.endswith("navigator.py")  # 2: INFO
    assert reached.line > 0 and reached.timestamp.seconds > 0


def test_the_layout_file_names_the_scene_and_the_goal_service(tmp_path):
    path = tmp_path / "turtlectl.json"
    result = subprocess.run(
        [*turtlectl(), "foxglove", "--layout", str(path)], capture_output=True, text=True, timeout=30
    )
    assert result.returncode == 0, result.stderr
    layout = json.loads(Path(path).read_text())
    assert {"configById", "layout"} <= set(layout)
    configs = layout["configById"]
    assert configs["3D!turtlectl"]["topics"]["scene"]["visible"] is True
    assert configs["CallService!goal"]["serviceName"] == "navigate_to"


SIM_AND_STATUS = """
[[node]]
name = "sim"
run = "sim"
[[node]]
name = "status_monitor"
run = "status_monitor"
required = false
respawn = false
"""


def test_channels_come_and_go_with_the_graph(tmp_path):
    path = tmp_path / "two.toml"
    path.write_text(SIM_AND_STATUS)
    port = free_port()
    with running_system(path, ready=("sim", "status_monitor")) as system:
        bridge = _bridge(system.endpoint, port)
        try:

            async def watch() -> list[str]:
                async with connect(f"ws://127.0.0.1:{port}", subprotocols=[SUBPROTOCOL], max_size=None) as ws:
                    client = Client(ws)
                    await client.advertised(("turtle1/pose", "robot/status"))
                    status = client.channels["robot/status"]["id"]
                    os.kill(system.alive["status_monitor"], signal.SIGKILL)
                    seen: list[str] = []

                    async def gone() -> None:
                        while True:
                            message = await ws.recv()
                            if isinstance(message, str):
                                op = json.loads(message)
                                seen.append(op["op"])
                                if op["op"] == "unadvertise" and status in op["channelIds"]:
                                    return

                    await asyncio.wait_for(gone(), 10.0)
                    return seen

            ops = asyncio.run(watch())
        finally:
            bridge.terminate()
            bridge.communicate(timeout=10)
    assert "unadvertise" in ops
