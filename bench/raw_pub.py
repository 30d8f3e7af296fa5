"""Baseline for bench/system.py: raw zenoh-python, no turtlectl code on the data path.

A peer that joins the router at ENDPOINT and publishes its wall clock (int64 ns,
little endian) on KEY at RATE Hz for SECONDS, on an absolute schedule.
Usage: python bench/raw_pub.py ENDPOINT KEY RATE SECONDS
"""

import json
import struct
import sys
import time

import zenoh


def main() -> None:
    endpoint, key, rate, seconds = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
    conf = zenoh.Config()
    conf.insert_json5("mode", '"peer"')
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5("connect/endpoints", json.dumps([endpoint]))
    conf.insert_json5("listen/endpoints", json.dumps(["tcp/127.0.0.1:0"]))
    with zenoh.open(conf) as session:
        pub = session.declare_publisher(key)
        start = time.monotonic()
        k = 0
        while time.monotonic() - start < seconds:
            k += 1
            time.sleep(max(0.0, start + k / rate - time.monotonic()))  # pacing: absolute schedule
            pub.put(struct.pack("<q", time.time_ns()))


if __name__ == "__main__":
    main()
