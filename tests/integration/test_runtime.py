"""The node runtime's lifecycle with a real router and a real node process: an exception in
node code is logged once, the shutdown hooks still run (a navigator's stop command is sent),
the session closes and the process exits 1, so the supervisor's respawn applies."""

from __future__ import annotations

import os
import queue
import subprocess
import sys
import textwrap

import pytest
import zenoh

from messages import Twist, decode
from runtime.config import ENV_VAR, NodeConfig, encode_config
from runtime.session import client_config, close_session, router_config
from tests.integration.harness import ROOT, free_port

pytestmark = pytest.mark.integration

STOP_KEY = "test/raising/cmd_vel"

#: a node kind that raises: its shutdown hook publishes a stop command, as the navigator's does
RAISING_NODE = textwrap.dedent(
    f"""
    import sys
    import msgspec
    from messages import Twist
    from runtime import run_main

    class Params(msgspec.Struct, forbid_unknown_fields=True):
        where: str = "timer"

    class Raising:
        def __init__(self, node):
            self.pub = node.publisher({STOP_KEY!r}, Twist)
            node.on_shutdown(self.stop)
            if node.params.where == "start":
                raise RuntimeError("raised while starting")
            node.timer(0.5, self.tick)

        def tick(self):
            raise RuntimeError("raised in a timer")

        def stop(self):
            self.pub.publish(Twist(linear=0.0, angular=0.0))
            print("stop command sent", file=sys.stderr, flush=True)

    run_main(Raising, Params)
    """
)


@pytest.mark.parametrize("where", ["timer", "start"])
def test_an_exception_in_node_code_runs_the_shutdown_hooks_and_exits_1(where):
    port = free_port()
    endpoint = f"tcp/127.0.0.1:{port}"
    router = zenoh.open(router_config(port))
    client = zenoh.open(client_config(endpoint, 5.0))
    stops: queue.SimpleQueue[Twist] = queue.SimpleQueue()
    client.declare_subscriber(STOP_KEY, lambda s: stops.put(decode(s.payload.to_bytes(), Twist)))
    config = NodeConfig(name="raising", kind="test", connect=endpoint, params={"where": where})
    env = dict(os.environ, **{ENV_VAR: encode_config(config)}, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen(
        [sys.executable, "-c", RAISING_NODE], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        _, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        close_session(client)
        close_session(router)
    assert proc.returncode == 1, err
    assert err.count("Traceback") == 1, err
    assert f"RuntimeError: raised {'in a timer' if where == 'timer' else 'while starting'}" in err
    assert "stop command sent" in err  # the hook ran
    if where == "timer":  # ready for 0.5 s: the router knows the subscriber, so the stop command arrives
        stop = stops.get(timeout=5)
        assert (stop.linear, stop.angular) == (0.0, 0.0)
