"""Baselines for bench/system.py: raw zenoh-python, no turtlectl code on the data path.

  python bench/raw_pub.py pub ENDPOINT KEY RATE SECONDS   publish the wall clock (int64 ns, little
                                                         endian) on KEY at RATE Hz, absolute schedule
  python bench/raw_pub.py sub ENDPOINT KEY SECONDS        a callback subscriber that counts samples
  python bench/raw_pub.py ring ENDPOINT KEY SECONDS       a subscriber keeping only the newest sample in
                                                         Zenoh (a ring channel of one), read at 10 Hz
  python bench/raw_pub.py idle ENDPOINT SECONDS           an open session doing nothing
  python bench/raw_pub.py once ENDPOINT KEY               a client that prints one sample's size and
                                                         exits (the floor of `turtlectl echo --once`)

Each is a peer that joins the router at ENDPOINT (`once`: a client, as the CLI), configured as
turtlectl's sessions are (multicast scouting off, scouting/delay 0).
"""

import json
import struct
import sys
import threading
import time

import zenoh


def config(mode: str, endpoint: str) -> zenoh.Config:
    conf = zenoh.Config()
    conf.insert_json5("mode", json.dumps(mode))
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5("scouting/delay", "0")
    conf.insert_json5("connect/endpoints", json.dumps([endpoint]))
    if mode == "peer":
        conf.insert_json5("listen/endpoints", json.dumps(["tcp/127.0.0.1:0"]))
    return conf


def main() -> None:
    what, endpoint = sys.argv[1], sys.argv[2]
    if what == "once":
        with zenoh.open(config("client", endpoint)) as session:
            got = threading.Event()
            size = []
            sub = session.declare_subscriber(sys.argv[3], lambda s: (size.append(len(s.payload)), got.set()))
            got.wait(10.0)
            sub.undeclare()
            print(size[0] if size else "nothing")
        return
    with zenoh.open(config("peer", endpoint)) as session:
        if what == "pub":
            key, rate, seconds = sys.argv[3], float(sys.argv[4]), float(sys.argv[5])
            pub = session.declare_publisher(key)
            start = time.monotonic()
            k = 0
            while time.monotonic() - start < seconds:
                k += 1
                time.sleep(max(0.0, start + k / rate - time.monotonic()))  # pacing: absolute schedule
                pub.put(struct.pack("<q", time.time_ns()))
        elif what == "sub":
            key, seconds = sys.argv[3], float(sys.argv[4])
            count = [0]
            sub = session.declare_subscriber(key, lambda _s: count.__setitem__(0, count[0] + 1))
            time.sleep(seconds)  # pacing: the measured window
            sub.undeclare()
        elif what == "ring":
            key, seconds = sys.argv[3], float(sys.argv[4])
            sub = session.declare_subscriber(key, zenoh.handlers.RingChannel(1))
            start = time.monotonic()
            k = 0
            while time.monotonic() - start < seconds:
                k += 1
                time.sleep(max(0.0, start + k / 10 - time.monotonic()))  # pacing: the reader's own 10 Hz tick
                sub.try_recv()
            sub.undeclare()
        else:
            time.sleep(float(sys.argv[3]))  # pacing: an idle session for the measured window


if __name__ == "__main__":
    main()
