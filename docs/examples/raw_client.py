"""A turtlectl client written from docs/interfaces.md alone: plain zenoh-python and plain
msgpack (msgspec.msgpack on dicts here; any msgpack library does), no turtlectl import.

    python docs/examples/raw_client.py [ENDPOINT] [DOMAIN]

ENDPOINT defaults to tcp/127.0.0.1:7447.  With DOMAIN (a system started with
``turtlectl --domain DOMAIN launch``) every key below is used under ``DOMAIN/``, which
the session's ``namespace`` does for us.  It lists the nodes, reads one status and the
world, teleports the turtle, drives it to a goal while printing the feedback, resets
the system (one Ack from each server) and cancels when nothing runs.
"""

import json
import math
import os
import queue
import secrets
import sys

import msgspec
import zenoh

endpoint = sys.argv[1] if len(sys.argv) > 1 else "tcp/127.0.0.1:7447"
domain = sys.argv[2] if len(sys.argv) > 2 else ""

conf = zenoh.Config()
conf.insert_json5("mode", '"client"')  # a client of the router, as turtlectl's tools
conf.insert_json5("connect/endpoints", json.dumps([endpoint]))
conf.insert_json5("scouting/multicast/enabled", "false")
if domain:
    conf.insert_json5("namespace", json.dumps(domain))  # every key becomes DOMAIN/<key>


def pack(type_name: str, **fields) -> tuple[bytes, zenoh.Encoding]:
    """A request: msgpack map with its type name (optional, checked if present), and the
    encoding that names the type."""
    return msgspec.msgpack.encode({"type": type_name, **fields}), zenoh.Encoding(f"application/msgpack;{type_name}")


def unpack(sample: zenoh.Sample) -> dict:
    """Any turtlectl payload: a msgpack map whose "type" names it by package (turtlectl/Ack)."""
    return msgspec.msgpack.decode(sample.payload.to_bytes())


with zenoh.open(conf) as session:
    # 1. the nodes: @turtlectl/node/<name>/<pid>/<host>/<start_ns>
    nodes = sorted(str(r.ok.key_expr).split("/")[2:4] for r in session.liveliness().get("@turtlectl/node/**") if r.ok)
    print(f"{len(nodes)} nodes:", ", ".join(f"{name} (pid {pid})" for name, pid in nodes))

    # 2. one TurtleStatus (10 Hz): theta is in degrees, [0, 360)
    statuses: queue.SimpleQueue = queue.SimpleQueue()
    sub = session.declare_subscriber("robot/status", lambda s: statuses.put(unpack(s)))
    status = statuses.get(timeout=5)
    sub.undeclare()
    print(
        f"status: x {status['x']:.2f} m, y {status['y']:.2f} m, heading {status['theta']:.1f} deg, battery {status['battery']:.1f} %"
    )

    # 3. the world: JSON, not msgpack
    world = json.loads(next(r.ok for r in session.get("turtlectl/world") if r.ok).payload.to_bytes())
    print(f"world: {world['size']:.3f} m square, {len(world['obstacles'])} obstacles")

    # 4. teleport: theta in radians, as turtlesim; the Ack comes once the new pose is out
    payload, encoding = pack("turtlectl/TeleportAbsolute", x=2.0, y=2.0, theta=math.radians(90.0))
    for reply in session.get("turtle1/teleport_absolute", payload=payload, encoding=encoding, timeout=5):
        answer = unpack(reply.ok) if reply.ok else msgspec.msgpack.decode(reply.err.payload.to_bytes())
        print("teleport:", answer)

    # 5. a goal: theta in degrees.  Hold a client token so that the navigator cancels the
    #    goal if this program goes away; keep every reply (ConsolidationMode.NONE).
    client_id = f"{os.getpid()}-{secrets.token_hex(4)}"
    token = session.liveliness().declare_token(f"@turtlectl/client/{client_id}")
    payload, encoding = pack("turtlectl/NavigateToRequest", x=5.0, y=2.0, theta=0.0, client=client_id)
    feedback = 0
    for reply in session.get(
        "navigate_to", payload=payload, encoding=encoding, consolidation=zenoh.ConsolidationMode.NONE, timeout=60
    ):
        if reply.err:  # an ErrorReply: the request could not be read
            print("error:", msgspec.msgpack.decode(reply.err.payload.to_bytes())["error"])
            break
        message = unpack(reply.ok)
        if message["type"] == "turtlectl/NavigateToFeedback":
            feedback += 1
            if feedback == 1:
                print(
                    f"feedback: {message['state']}, {message['distance_remaining']:.2f} m to go, eta {message['eta']:.1f} s"
                )
        elif message["type"] == "turtlectl/NavigateToResponse":
            outcome = "reached" if message["success"] else f"not reached ({message['reason']})"
            print(
                f"goal {outcome} in {message['time_taken']:.2f} s after {feedback} feedback replies: "
                f"({message['x']:.3f}, {message['y']:.3f}, {message['theta']:.1f} deg), error {message['position_error']:.4f} m"
            )
    token.undeclare()

    # 6. reset: served by the sim and the status monitor; both Acks need QueryTarget.ALL
    #    and ConsolidationMode.NONE (the default consolidation keeps one reply per key)
    payload, encoding = pack("turtlectl/Reset")
    acks = [
        unpack(r.ok)["detail"]
        for r in session.get(
            "reset",
            payload=payload,
            encoding=encoding,
            target=zenoh.QueryTarget.ALL,
            consolidation=zenoh.ConsolidationMode.NONE,
            timeout=5,
        )
        if r.ok
    ]
    print(f"reset: {len(acks)} acks:", "; ".join(sorted(acks)))

    # 7. cancel with no goal running: Ack ok=false
    payload, encoding = pack("turtlectl/Cancel")
    ack = unpack(next(r.ok for r in session.get("navigate_to/cancel", payload=payload, encoding=encoding) if r.ok))
    print(f"cancel: ok={ack['ok']} ({ack['detail']})")
