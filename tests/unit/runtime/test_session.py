"""Session settings that need no running Zenoh."""

from turtlectl.runtime.session import local_address_towards


def test_nodes_listen_where_they_reach_the_router():
    assert local_address_towards("tcp/127.0.0.1:7447") == "127.0.0.1"
    assert local_address_towards("tcp/localhost:7447") in ("127.0.0.1", "[::1]")
    assert local_address_towards("tcp/[::1]:7447") == "[::1]"
    assert local_address_towards("not an endpoint") == "127.0.0.1"
