"""runtime.endpoint.peer_timeout: the bound within which a silent peer is detected, and what every
session's configuration takes from it."""

from __future__ import annotations

import json

import pytest

from turtlectl.runtime.endpoint import DEFAULT_PEER_TIMEOUT, PEER_TIMEOUT_ENV, peer_timeout
from turtlectl.runtime.session import listen_hosts, peer_config


def test_default_and_given(monkeypatch):
    monkeypatch.delenv(PEER_TIMEOUT_ENV, raising=False)
    assert peer_timeout() == DEFAULT_PEER_TIMEOUT == 3.0
    monkeypatch.setenv(PEER_TIMEOUT_ENV, "7.5")
    assert peer_timeout() == 7.5


@pytest.mark.parametrize("value", ["abc", "0.4", "60.1", "nan", "-1"])
def test_a_bad_value_names_the_variable_and_the_range(value, monkeypatch):
    monkeypatch.setenv(PEER_TIMEOUT_ENV, value)
    with pytest.raises(ValueError, match=rf"^TURTLECTL_PEER_TIMEOUT='{value}': give seconds from 0.5 to 60$"):
        peer_timeout()


def test_every_session_s_lease_is_the_bound(monkeypatch):
    monkeypatch.setenv(PEER_TIMEOUT_ENV, "2")
    conf = peer_config("tcp/127.0.0.1:7447")
    assert json.loads(conf.get_json("transport/link/tx/lease")) == 2000
    # a blocked link stalls the whole process's routing: it is closed sooner than a silent one
    assert json.loads(conf.get_json("transport/link/tx/queue/congestion_control/block/wait_before_close")) == 500_000
    monkeypatch.setenv(PEER_TIMEOUT_ENV, "0.5")
    conf = peer_config("tcp/127.0.0.1:7447")
    assert json.loads(conf.get_json("transport/link/tx/queue/congestion_control/block/wait_before_close")) == 500_000


def test_a_router_on_a_network_address_listens_on_loopback_too():
    assert listen_hosts("192.168.1.20") == ["192.168.1.20", "127.0.0.1"]
    assert listen_hosts("127.0.0.1") == ["127.0.0.1"]
    assert listen_hosts("0.0.0.0") == ["0.0.0.0"]
    assert listen_hosts("[fd00::2]") == ["[fd00::2]", "[::1]"]
