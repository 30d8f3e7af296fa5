"""``launch --web PORT`` (``make run``): the plan gains a web page node, as a ``[[node]]`` with
``run = "web"`` would add one; a file that runs one keeps its own."""

from __future__ import annotations

from pathlib import Path

import pytest

from turtlectl.cli.system.launchfile import LaunchFileError
from turtlectl.cli.system.overrides import launch_plan, node_config

ROOT = Path(__file__).resolve().parents[4]


def test_web_adds_the_page_on_loopback() -> None:
    plan = launch_plan(ROOT / "launch.toml", [], [], [], web=8123)
    entry = plan.launch.node[-1]
    assert (entry.name, entry.run, entry.required) == ("web", "web", False)
    assert plan.params["web"]["port"] == 8123 and plan.params["web"]["host"] == "127.0.0.1"
    config = node_config(plan, "web", "tcp/127.0.0.1:7447")
    assert config.kind == "web" and config.params["port"] == 8123
    assert [e.name for e in launch_plan(ROOT / "launch.toml", [], [], []).launch.node] == [
        e.name for e in plan.launch.node[:-1]
    ]


def test_a_file_that_runs_a_page_keeps_its_own(tmp_path: Path) -> None:
    text = (ROOT / "launch.toml").read_text() + '\n[[node]]\nname = "page"\nrun = "web"\nparams = { port = 9001 }\n'
    (tmp_path / "launch.toml").write_text(text)
    plan = launch_plan(tmp_path / "launch.toml", [], [], [], web=8123)
    assert [e.name for e in plan.launch.node if e.run == "web"] == ["page"]
    assert plan.params["page"]["port"] == 9001


def test_a_node_named_web_already_gives_the_page_another_name(tmp_path: Path) -> None:
    text = (ROOT / "launch.toml").read_text().replace('name = "navigator"', 'name = "web"', 1)
    (tmp_path / "launch.toml").write_text(text)
    plan = launch_plan(tmp_path / "launch.toml", [], [], [], web=8123)
    assert plan.launch.node[-1].name == "web2" and plan.launch.node[-1].run == "web"


def test_a_bad_web_parameter_in_a_file_is_named(tmp_path: Path) -> None:
    text = (ROOT / "launch.toml").read_text() + '\n[[node]]\nname = "page"\nrun = "web"\nparams = { role = "admin" }\n'
    (tmp_path / "launch.toml").write_text(text)
    with pytest.raises(
        LaunchFileError, match=r"\(page\)\.params\.role must be one of operator, teleop, viewer \(got \"admin\"\)"
    ):
        launch_plan(tmp_path / "launch.toml", [], [], [])


def test_the_page_stays_on_loopback_unless_told(tmp_path: Path) -> None:
    """The rule of the router's --listen: beyond loopback only when asked (the page has no logins)."""
    from turtlectl.nodes.params import WebParams

    assert WebParams(host="127.0.0.1").host == "127.0.0.1" and WebParams(host="::1").host == "::1"
    with pytest.raises(ValueError, match=r"host 0.0.0.0 reaches beyond this machine.*role \(viewer\).*insecure = true"):
        WebParams(host="0.0.0.0", role="viewer")
    with pytest.raises(ValueError, match="host 'robot.local' is not an IP address"):
        WebParams(host="robot.local")
    assert WebParams(host="0.0.0.0", insecure=True).insecure
    text = (
        ROOT / "launch.toml"
    ).read_text() + '\n[[node]]\nname = "page"\nrun = "web"\nparams = { host = "192.168.1.4" }\n'
    (tmp_path / "launch.toml").write_text(text)
    with pytest.raises(LaunchFileError, match=r"\(page\)\.params: host 192.168.1.4 reaches beyond this machine"):
        launch_plan(tmp_path / "launch.toml", [], [], [])
