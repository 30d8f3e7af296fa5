"""Authentication: `launch --secure` lets in only the sessions that log in: its nodes
with a login each, as clients of the router (nobody can reach a node directly), and local
clients with the login the supervisor writes to the credentials file."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import time
from pathlib import Path

import psutil
import pytest
import zenoh

from tests.integration.harness import credentials_at, running_system, turtlectl
from tests.integration.test_log import Lines
from turtlectl.messages import Pose, Twist, encode, encoding_for
from turtlectl.messages.keys import CMD_VEL, NAVIGATE_TO
from turtlectl.runtime.client import credentials
from turtlectl.runtime.client.errors import ExitCode
from turtlectl.runtime.config import Credentials
from turtlectl.runtime.session import client_config, peer_config

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    """The credentials file of this module's systems (never the user's own)."""
    with credentials_at(tmp_path_factory.mktemp("credentials") / "credentials.json") as path:
        yield path


@pytest.fixture(scope="module")
def secure(store):
    with running_system(extra_args=("--secure",)) as system:
        yield system


def run(system, *args: str, store: Path | None = None) -> tuple[subprocess.CompletedProcess[str], float]:
    env = {**os.environ, **({credentials.ENV: str(store)} if store else {})}
    started = time.monotonic()
    result = subprocess.run(
        [*turtlectl(), *args, "--connect", system.endpoint],
        capture_output=True,
        text=True,
        timeout=30,
        stdin=subprocess.DEVNULL,
        env=env,
    )
    return result, time.monotonic() - started


def test_a_secure_system_runs_and_its_local_clients_log_in(secure, store):
    assert stat.S_IMODE(store.stat().st_mode) == 0o600
    entry = json.loads(store.read_text())[secure.endpoint]
    assert {role: login["user"] for role, login in entry.items()} == {r: r for r in ("viewer", "operator", "teleop")}
    assert all(len(login["password"]) >= 32 for login in entry.values())
    secure.teleport(3.0, 5.5, 0.0)
    goal, _ = run(secure, "goto", "5", "5.5", "0")
    assert goal.returncode == 0, goal.stderr
    listed, _ = run(secure, "list", "--json")
    assert {n["name"] for n in json.loads(listed.stdout)["nodes"]} == {
        "sim",
        "navigator",
        "status_monitor",
        "obstacle_detector",
    }


def test_a_client_without_the_login_or_with_a_wrong_one_is_refused_within_3_s(secure, tmp_path):
    nothing = tmp_path / "none.json"
    refused, took = run(secure, "echo", "robot/status", "--once", store=nothing)
    assert refused.returncode == ExitCode.UNREACHABLE and took < 3.0 + 1.5, took  # Python's start included
    assert refused.stderr.strip().splitlines() == [
        f"turtlectl: error: the router at {secure.endpoint} did not let this client in within 2.5 s: a `launch --secure` "
        f"system takes only clients with its login, and TURTLECTL_CREDENTIALS names {nothing}, which does not exist; "
        f"one with --tls speaks TLS only (connect with tls/HOST:PORT)"
    ]
    wrong = tmp_path / "wrong.json"
    credentials.publish(secure.endpoint, {"operator": Credentials(user="operator", password="guessed")}, wrong)
    refused, _ = run(secure, "goto", "8", "5", "0", store=wrong)
    assert refused.returncode == ExitCode.UNREACHABLE
    assert "its login in the credentials file was refused" in refused.stderr and "Traceback" not in refused.stderr


def test_nothing_a_process_without_the_login_sends_reaches_the_turtle(secure):
    """A rogue peer and a rogue client, no login: the router never lets them in."""
    with pytest.raises(zenoh.ZError):
        zenoh.open(client_config(secure.endpoint, 1.0))
    assert_does_not_drive(secure, zenoh.open(peer_config(secure.endpoint)))  # a peer opens anyway, trying to join


def assert_does_not_drive(secure, rogue: zenoh.Session) -> None:
    """``rogue`` publishes turtle1/cmd_vel at 50 Hz for 2 s: the turtle stays put."""
    secure.teleport(4.0, 4.0, 0.0)
    try:
        pub = rogue.declare_publisher(CMD_VEL, encoding=zenoh.Encoding(encoding_for(Twist)))
        for _ in range(100):
            pub.put(encode(Twist(linear=2.0)))
            time.sleep(0.02)  # pacing: the rogue's publishing rate
        pose = secure.latest_pose()
        assert (pose.x, pose.y, pose.linear_velocity) == (4.0, 4.0, 0.0), pose
    finally:
        rogue.close()


def test_the_nodes_of_a_secure_system_accept_no_connection_of_their_own(secure):
    """Peers connected to each other bypass what the router checks: in --secure mode nodes are
    clients of the router and listen on no port (the default system's nodes are peers and do)."""
    for name, pid in secure.alive.items():
        listening = [c for c in psutil.Process(pid).net_connections() if c.status == psutil.CONN_LISTEN]
        assert listening == [], (name, listening)


def test_the_login_is_withdrawn_when_the_system_stops(store):
    with running_system(extra_args=("--secure",)) as system:
        assert system.endpoint in json.loads(store.read_text())
        assert system.stop() == 0
    assert system.endpoint not in json.loads(store.read_text())


def login(system, role: str) -> zenoh.Session:
    return zenoh.open(client_config(system.endpoint, 3.0, "", credentials.for_endpoint(system.endpoint, as_role=role)))


def test_a_viewer_watches_but_its_goto_is_not_permitted(secure):
    viewer = {"TURTLECTL_ROLE": "viewer"}
    status, _ = run_as(secure, viewer, "echo", "robot/status", "--once", "--json")
    assert status.returncode == 0 and json.loads(status.stdout)["type"] == "turtlectl/TurtleStatus", status.stderr
    goal, _ = run_as(secure, viewer, "goto", "5", "5", "0")
    assert goal.returncode == ExitCode.FAILED
    assert goal.stderr.strip() == (
        "turtlectl: error: not permitted: the viewer role may not call navigate_to on this --secure system "
        "(may: operator, teleop; TURTLECTL_ROLE chooses the role)"
    )
    drive, _ = run_as(secure, {}, "pub", "turtle1/cmd_vel", '{"linear": 1.0}', "--once")  # operator
    assert drive.returncode == ExitCode.FAILED and "may: teleop" in drive.stderr


def test_a_viewer_s_echo_is_listed_to_an_operator_the_router_lets_every_role_declare_its_presence(secure):
    echo = subprocess.Popen(
        [*turtlectl(), "echo", "robot/status", "--connect", secure.endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        stdin=subprocess.DEVNULL,
        text=True,
        env={**os.environ, "TURTLECTL_ROLE": "viewer"},
    )
    try:
        assert echo.stdout.readline()  # its session is open and subscribed
        deadline = time.monotonic() + 10
        while True:
            graph, _ = run_as(secure, {}, "list", "--json")  # operator
            found = [c for c in json.loads(graph.stdout)["clients"] if c["pid"] == echo.pid]
            topic = next(t for t in json.loads(graph.stdout)["topics"] if t["key"] == "robot/status")
            if found and f"echo-{echo.pid}" in topic["subscribers"]:
                break
            assert time.monotonic() < deadline, graph.stdout  # the router dropped the viewer's tokens
            time.sleep(0.1)  # polling the graph under a deadline
        assert found[0]["tool"] == "echo"
    finally:
        echo.kill()
        echo.wait()


def test_a_rogue_operator_publishing_cmd_vel_does_not_move_the_turtle(secure):
    assert_does_not_drive(secure, login(secure, "operator"))
    moved, _ = run_as(secure, {"TURTLECTL_ROLE": "teleop"}, "pub", "turtle1/cmd_vel", '{"linear": 1.0}', "--once")
    assert moved.returncode == 0, moved.stderr
    secure.wait_moving(0.5)  # the teleop role may drive


def test_an_operator_spawns_a_turtle_the_teleop_role_drives_and_the_operator_kills(secure):
    """On a --secure system a spawned turtle can be driven (a role may publish turtle2/cmd_vel)."""
    spawned, _ = run_as(secure, {}, "spawn", "2", "2", "0", "--name", "secured")
    assert spawned.returncode == 0 and spawned.stdout.strip() == "secured", spawned.stderr
    try:
        moved, _ = run_as(secure, {"TURTLECTL_ROLE": "teleop"}, "pub", "secured/cmd_vel", '{"linear": 1.0}', "--once")
        assert moved.returncode == 0, moved.stderr
        pose = secure.collect("secured/pose", Pose, 40, timeout=5.0)[-1][1]
        assert pose.linear_velocity > 0.0 or pose.x > 2.0, pose
    finally:
        killed, _ = run_as(secure, {}, "kill", "secured")
    assert killed.returncode == 0, killed.stderr


def test_only_the_navigator_may_serve_navigate_to(secure):
    queries = []
    impostor = login(secure, "operator")
    try:
        impostor.declare_queryable(NAVIGATE_TO, lambda q: queries.append(q))
        secure.teleport(3.0, 5.5, 0.0)
        goal, _ = run_as(secure, {}, "goto", "4", "5.5", "0")
        assert goal.returncode == 0, goal.stderr  # the navigator's answer
        assert queries == []  # the impostor never got the goal
    finally:
        impostor.close()


def test_every_nodes_log_reaches_a_viewer_through_the_routers_rules(secure):
    """Each node may publish its own log key and answer a get on it for its recent
    records, and a viewer may read both (the router drops what it does not allow without a word)."""
    viewer = {"TURTLECTL_ROLE": "viewer"}
    recent, _ = run_as(secure, viewer, "log", "--json")
    assert recent.returncode == 0, recent.stderr
    ready = {r["node"] for r in map(json.loads, recent.stdout.splitlines()) if r["message"].startswith("ready (pid")}
    assert ready == {"sim", "navigator", "status_monitor", "obstacle_detector"}
    follow = subprocess.Popen(
        [*turtlectl(), "log", "-f", "--node", "navigator", "--json", "--connect", secure.endpoint],
        env={**os.environ, **viewer},
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        text=True,
    )
    try:
        lines = Lines(follow)
        lines.until(lambda r: r["message"].startswith("ready (pid"))
        changed, _ = run(secure, "param", "set", "navigator", "goal_timeout", "40")  # as operator
        assert changed.returncode == 0, changed.stderr
        lines.until(lambda r: r["message"].endswith("-> 40.0"))  # published live, through the router
    finally:
        follow.kill()
        follow.wait()


def run_as(system, env: dict[str, str], *args: str) -> tuple[subprocess.CompletedProcess[str], float]:
    before = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    try:
        return run(system, *args)
    finally:
        for k, v in before.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def test_secure_over_mutual_tls_takes_only_certificates_its_authority_signed(store, tmp_path, monkeypatch):
    """Authentication on loopback (the two-host version runs in test_hosts where namespaces can be made)."""
    from turtlectl.cli.system.certs import make

    make(tmp_path / "tls", [])
    make(tmp_path / "other", [])
    monkeypatch.setenv("TURTLECTL_TLS", str(tmp_path / "tls"))
    with running_system(extra_args=("--secure", "--tls", str(tmp_path / "tls"))) as system:
        endpoint = system.endpoint
        assert endpoint.startswith("tls/127.0.0.1:")
        goal = subprocess.run(
            [*turtlectl(), "goto", "6", "5.5", "0", "--connect", endpoint], capture_output=True, text=True, timeout=30
        )
        assert goal.returncode == 0, goal.stderr
        plaintext = endpoint.replace("tls/", "tcp/")
        plain = subprocess.run([*turtlectl(), "list", "--connect", plaintext], capture_output=True, text=True)
        assert plain.returncode == ExitCode.UNREACHABLE and "speaks TLS only" in plain.stderr
        monkeypatch.setenv("TURTLECTL_TLS", str(tmp_path / "other"))
        foreign = subprocess.run([*turtlectl(), "list", "--connect", endpoint], capture_output=True, text=True)
        assert foreign.returncode == ExitCode.UNREACHABLE and "is not one its authority signed" in foreign.stderr


def test_a_second_secure_launch_on_a_busy_port_leaves_the_running_system_s_logins(secure, store):
    """A failed launch leaves the running system's entry alone: withdrawn, it would lock its clients out."""
    port = secure.endpoint.rsplit(":", 1)[1]
    second = subprocess.run(
        [*turtlectl(), "launch", "--secure", "--port", port], capture_output=True, text=True, timeout=30
    )
    assert second.returncode == ExitCode.CANNOT_START, second.stdout + second.stderr
    assert secure.endpoint in json.loads(store.read_text())
    still, _ = run(secure, "echo", "robot/status", "--once")
    assert still.returncode == 0, still.stderr


LAPS = '''
import msgspec

from turtlectl import Interface, Message


class NoParams(msgspec.Struct, forbid_unknown_fields=True):
    pass


class Laps(Message, tag="SecureLaps"):
    laps: int


class LapsDone(Message, tag="SecureLapsDone"):
    done: int


class LapsResult(Message, tag="SecureLapsResult"):
    success: bool = False
    reason: str = ""
    laps: int = 0


class Patrol:
    """A goal service of a node class that declares no Interface (it serves under its own name)."""

    Params = NoParams

    def __init__(self, node):
        self.done = 0
        self.server = node.goal_server(
            f"{node.name}/laps", Laps, LapsDone, LapsResult, execute=self.start,
            feedback=lambda goal: LapsDone(done=self.done), feedback_rate=5.0,
        )
        node.timer(0.2, self.lap)

    def start(self, goal):
        self.done = 0

    def lap(self):
        goal = self.server.goal
        if goal is not None:
            self.done += 1
            if self.done >= goal.request.laps:
                goal.finish(LapsResult(success=True, laps=self.done))


class Drill(Patrol):
    """The same goal service, its node class declaring its Interface."""

    Interface = Interface(
        serves=("drill/laps", "drill/laps/cancel"),
        publishes=("drill/laps/feedback",),
        watches=("@turtlectl/client/**",),
    )
'''


@pytest.fixture(scope="module")
def secure_goals(store, tmp_path_factory):
    """A --secure system with a user's goal services: one whose node declares its Interface, one
    whose node declares none."""
    project = tmp_path_factory.mktemp("goals")
    (project / "laps.py").write_text(LAPS)
    (project / "launch.toml").write_text(
        '[[node]]\nname = "sim"\nrun = "sim"\n\n'
        '[[node]]\nname = "patrol"\nrun = "./laps.py:Patrol"\n\n'
        '[[node]]\nname = "drill"\nrun = "./laps.py:Drill"\n'
    )
    with running_system(
        project / "launch.toml", ready=("sim", "patrol", "drill"), cwd=project, extra_args=("--secure",)
    ) as system:
        yield system


def cancel_answers(system, role: str, key: str) -> list[bytes]:
    """What ``key`` answers a Cancel sent through the router as ``role`` (its rules alone: no client check)."""
    from turtlectl.messages import Cancel

    session = login(system, role)
    try:
        replies = session.get(key, payload=encode(Cancel()), encoding=encoding_for(Cancel), timeout=2.0)
        return [r.ok.payload.to_bytes() for r in replies if r.ok is not None]
    finally:
        session.close()


@pytest.mark.parametrize("service", ["drill/laps", "patrol/laps"])
def test_an_operator_sends_goals_to_and_cancels_any_goal_service_a_viewer_none(secure_goals, service):
    sent, _ = run_as(secure_goals, {}, "action", "send-goal", service, '{"laps": 2}', "--json")  # operator
    assert sent.returncode == 0 and '"laps":2' in sent.stdout.replace(" ", ""), sent.stdout + sent.stderr
    assert len(cancel_answers(secure_goals, "operator", f"{service}/cancel")) == 1  # no goal runs: an Ack
    assert cancel_answers(secure_goals, "viewer", f"{service}/cancel") == []  # the router drops it
    viewer, _ = run_as(secure_goals, {"TURTLECTL_ROLE": "viewer"}, "action", "send-goal", service, '{"laps": 1}')
    assert viewer.returncode == ExitCode.FAILED
    assert viewer.stderr.strip() == (
        f"turtlectl: error: not permitted: the viewer role may not call {service} on this --secure system "
        "(may: operator, teleop; TURTLECTL_ROLE chooses the role)"
    )


def test_each_host_its_own_certificate_and_a_denied_host_is_shut_out(store, tmp_path, monkeypatch):
    """`certs DIR --issue NAME` gives a host a certificate of its own and, with --system, the
    running system's credentials entry; `launch --deny-host NAME` lets nothing of that host
    through, whatever its login, while the other hosts work on."""
    from turtlectl.cli.system.certs import make

    tls = tmp_path / "tls"
    make(tls, [])
    for host in ("robot7", "robot8"):
        issued = subprocess.run([*turtlectl(), "certs", str(tls), "--issue", host], capture_output=True, text=True)
        assert issued.returncode == 0, issued.stderr
        assert f"export TURTLECTL_TLS={tls / 'hosts' / host}" in issued.stdout
    unknown = subprocess.run(
        [*turtlectl(), "launch", "--secure", "--tls", str(tls), "--deny-host", "robot9", "--check"],
        capture_output=True,
        text=True,
    )
    assert unknown.returncode == ExitCode.BAD_INPUT and "robot9: no certificate was issued" in unknown.stderr
    monkeypatch.setenv("TURTLECTL_TLS", str(tls))
    with running_system(extra_args=("--secure", "--tls", str(tls), "--deny-host", "robot8")) as system:

        def as_host(host: str, *argv: str) -> subprocess.CompletedProcess[str]:
            handed = subprocess.run(
                [*turtlectl(), "certs", str(tls), "--issue", host, "--system", system.endpoint],
                capture_output=True,
                text=True,
            )
            assert handed.returncode == 0, handed.stderr
            folder = tls / "hosts" / host
            assert f"export TURTLECTL_CREDENTIALS={folder / 'credentials.json'}" in handed.stdout
            env = {
                **os.environ,
                "TURTLECTL_TLS": str(folder),
                credentials.ENV: str(folder / "credentials.json"),
            }
            return subprocess.run(
                [*turtlectl(), *argv, "--connect", system.endpoint],
                capture_output=True,
                text=True,
                timeout=60,
                stdin=subprocess.DEVNULL,
                env=env,
            )

        allowed = as_host("robot7", "param", "get", "navigator", "goal_timeout")
        assert allowed.returncode == 0 and allowed.stdout.strip(), allowed.stderr
        denied = as_host("robot8", "param", "get", "navigator", "goal_timeout")
        assert denied.returncode != 0 and not denied.stdout.strip(), denied.stdout + denied.stderr
