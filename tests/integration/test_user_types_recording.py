"""A user's own message type (tests/integration/test_user_types.py's WallState, published
by the user node ./wall.py:Wall) is recorded with its JSON Schema as a built-in is, `info` names
it, `play` publishes it back byte for byte under its own encoding, and `turtlectl foxglove`
advertises it with its schema, its messages valid against it; a payload no node describes is
recorded raw, without an error."""

from __future__ import annotations

import asyncio
import json
import queue
import signal
import subprocess
import threading
import time

import jsonschema
import msgspec
import pytest
import zenoh
from websockets.asyncio.client import connect

from tests.integration.harness import Router, free_port, turtlectl
from tests.integration.test_foxglove import SUBPROTOCOL, Client, _bridge
from tests.integration.test_user_types import walls_system
from turtlectl.runtime.session import client_config, close_session

pytestmark = pytest.mark.integration

ENCODING = "application/msgpack;wall/WallState"
MYSTERY = msgspec.msgpack.encode({"type": "Mystery", "a": 1})


@pytest.fixture(scope="module")
def system(tmp_path_factory):
    with walls_system(tmp_path_factory) as system:
        yield system


@pytest.fixture(scope="module")
def recording(system, tmp_path_factory):
    """wall/state and raw/data recorded for 3 s (raw/data: an undescribed payload put meanwhile);
    the file, the recorder's result, and the wall/state payloads a subscriber saw, by seq."""
    path = tmp_path_factory.mktemp("rec") / "wall.mcap"
    session = system.session
    seen: dict[int, tuple[bytes, str]] = {}

    def on_wall(sample: zenoh.Sample) -> None:
        payload = sample.payload.to_bytes()
        seen[msgspec.msgpack.decode(payload)["seq"]] = (payload, str(sample.encoding))

    sub = session.declare_subscriber("wall/state", on_wall)
    done = threading.Event()

    def put_raw() -> None:
        while not done.wait(0.1):  # pacing: a raw publisher at 10 Hz
            session.put("raw/data", MYSTERY, encoding="application/msgpack;Mystery")

    putter = threading.Thread(target=put_raw, daemon=True)
    putter.start()
    try:
        result = subprocess.run(
            [*turtlectl(), "record", "wall/state", "raw/data", "--duration", "3", "-o", str(path)]
            + ["--connect", system.endpoint],
            capture_output=True,
            text=True,
            timeout=60,
        )
    finally:
        done.set()
        putter.join(5)
        sub.undeclare()
    return path, result, dict(seen)


def _read(path):
    """(schema or None, channel, message) of every message, straight from the MCAP file."""
    from mcap.reader import make_reader

    with open(path, "rb") as f:
        return list(make_reader(f).iter_messages(log_time_order=True))


def test_record_gives_a_user_type_its_json_schema(recording):
    path, result, _ = recording
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr and "rror" not in result.stderr, result.stderr
    walls = [(s, c, m) for s, c, m in _read(path) if c.topic == "wall/state"]
    assert len(walls) >= 10, len(walls)
    schema, channel, _ = walls[0]
    assert schema is not None and schema.name == "wall/WallState" and schema.encoding == "jsonschema"
    assert channel.message_encoding == "json" and channel.metadata["zenoh_encoding"] == ENCODING
    document = json.loads(schema.data)
    assert document["title"] == "wall/WallState" and {"distance", "side", "corners"} <= set(document["properties"])
    for _, _, message in walls:
        data = json.loads(message.data)
        jsonschema.validate(data, document)
        assert data["distance"] == 0.75 and data["corners"] == [{"x": 1.0, "y": 2.0}]


def test_an_undescribed_payload_is_recorded_raw(recording):
    path, result, _ = recording
    raws = [(s, c, m) for s, c, m in _read(path) if c.topic == "raw/data"]
    assert raws, result.stderr
    assert all(s is None and c.message_encoding == "application/msgpack;Mystery" for s, c, _ in raws)
    assert all(bytes(m.data) == MYSTERY for _, _, m in raws)


def test_info_names_the_user_type_and_counts_it(recording):
    path = recording[0]
    count = sum(1 for _, c, _ in _read(path) if c.topic == "wall/state")
    result = subprocess.run([*turtlectl(), "info", str(path)], capture_output=True, text=True, timeout=30)
    assert result.returncode == 0, result.stderr
    assert any(
        line.split()[:3] == ["wall/state", "wall/WallState", str(count)] for line in result.stdout.splitlines()
    ), result.stdout
    data = msgspec.json.decode(
        subprocess.run([*turtlectl(), "info", str(path), "--json"], capture_output=True, timeout=30).stdout
    )
    topics = {t["key"]: t for t in data["topics"]}
    assert topics["wall/state"]["type_name"] == "wall/WallState" and topics["wall/state"]["count"] == count


def test_play_publishes_a_user_type_back_identical(recording):
    """Into a router with no system at all: the type is known from the file alone."""
    path, _, seen = recording
    count = sum(1 for _, c, _ in _read(path) if c.topic == "wall/state")
    router = Router()
    router.start()
    try:
        session = zenoh.open(client_config(router.endpoint, 3.0))
        got: queue.SimpleQueue[tuple[bytes, str]] = queue.SimpleQueue()
        sub = session.declare_subscriber("wall/state", lambda s: got.put((s.payload.to_bytes(), str(s.encoding))))
        try:
            result = subprocess.run(
                [*turtlectl(), "play", str(path), "--topics", "wall/state", "--keep-stamps", "--rate", "4"]
                + ["--connect", router.endpoint],
                capture_output=True,
                text=True,
                timeout=60,
            )
            assert result.returncode == 0, result.stderr
            assert f"played {count} messages" in result.stdout, result.stdout + result.stderr
            played: list[tuple[bytes, str]] = []
            deadline = time.monotonic() + 5
            while len(played) < count and time.monotonic() < deadline:
                try:
                    played.append(got.get(timeout=0.1))
                except queue.Empty:
                    pass
        finally:
            sub.undeclare()
            close_session(session)
    finally:
        router.kill()
    assert len(played) == count
    for payload, encoding in played:
        assert encoding == ENCODING
        seq = msgspec.msgpack.decode(payload)["seq"]
        if seq in seen:  # the subscriber of the fixture saw it too: the same bytes
            assert (payload, encoding) == seen[seq]
    assert sum(1 for payload, _ in played if msgspec.msgpack.decode(payload)["seq"] in seen) >= count - 2


def test_play_describes_the_user_types_it_plays(recording):
    """Into a bare router (no node uses WallState): while `play` runs, it describes the type on
    turtlectl/types/wall.WallState/play, so echo and `interface show` understand it (before: undescribed)."""
    path = recording[0]
    router = Router()
    router.start()
    player = subprocess.Popen(
        [*turtlectl(), "play", str(path), "--topics", "wall/state", "--loop", "--connect", router.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        # echo --once returns on the first message played: the description is declared before it
        echoed = subprocess.run(
            [*turtlectl(), "echo", "wall/state", "--once", "--connect", router.endpoint],
            capture_output=True,
            text=True,
            timeout=60,
        )
        shown = subprocess.run(
            [*turtlectl(), "interface", "show", "WallState", "--connect", router.endpoint],
            capture_output=True,
            text=True,
            timeout=60,
        )
    finally:
        player.send_signal(signal.SIGINT)
        try:
            out, err = player.communicate(timeout=20)
        finally:
            if player.poll() is None:
                player.kill()
            router.kill()
    assert echoed.returncode == 0, echoed.stderr
    assert "# wall/WallState" in echoed.stdout and "(undescribed)" not in echoed.stdout, echoed.stdout
    assert "distance: 0.75" in echoed.stdout, echoed.stdout
    assert shown.returncode == 0, shown.stdout + shown.stderr
    described_by = [line for line in shown.stdout.splitlines() if line.startswith("described by:")]
    assert described_by and "play" in described_by[0].split("(hash")[0], shown.stdout
    assert player.returncode == 0 and "Traceback" not in err, err


def test_foxglove_advertises_a_user_type_with_its_schema(system):
    port = free_port()
    bridge = _bridge(system.endpoint, port)
    try:

        async def session() -> tuple[Client, dict[str, list[bytes]]]:
            async with connect(f"ws://127.0.0.1:{port}", subprotocols=[SUBPROTOCOL], max_size=None) as ws:
                client = Client(ws)
                await client.advertised(("wall/state",), timeout=20.0)
                return client, await client.messages(("wall/state",), 3)

        client, got = asyncio.run(session())
    finally:
        bridge.terminate()
        out, err = bridge.communicate(timeout=10)
    assert "Traceback" not in err, err
    channel = client.channels["wall/state"]
    assert channel["encoding"] == "json" and channel["schemaEncoding"] == "jsonschema"
    assert channel["schemaName"] == "wall/WallState"
    schema = json.loads(channel["schema"])
    for payload in got["wall/state"]:
        message = json.loads(payload)
        jsonschema.validate(message, schema)
        assert message["distance"] == 0.75
