"""Client sessions (of the command-line tools and of ``turtlectl.Client``), and checks of what
users type for them.

A session is opened for an endpoint, in a domain, with the login of a role: all three are
arguments of ``client_session`` (their defaults: the environment's), and the session keeps its
domain and role (``domain_of``, ``logged_in_as``) for what is done with it later.  Nothing here
prints; functions return data or raise a turtlectl.Error (runtime.client.errors).  Service calls
live in runtime.client.services; the check of an endpoint in runtime.client.checks.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import socket
import time
from collections.abc import Iterator

import zenoh

from turtlectl.messages.keys import (
    DOMAIN_GRAPHS,
    DOMAIN_TOKEN_PREFIX,
    FIRST_TURTLE,
    GRAPH,
    NAVIGATE_TO,
    NODE_TOKEN_PREFIX,
    SERVICES,
    TOPICS,
    client_token,
    parse_domain_token,
    resolve,
    turtle_namespace,
)
from turtlectl.runtime.client import credentials, presence
from turtlectl.runtime.client.checks import ENDPOINT_RE, endpoint
from turtlectl.runtime.client.errors import BadInput, Failed, TurtlectlError, Unreachable
from turtlectl.runtime.client.graph import Graph, build_graph, without_client
from turtlectl.runtime.client.sigint import sigint_deferred
from turtlectl.runtime.endpoint import default_domain
from turtlectl.runtime.roles import GOAL_SENDERS, ROLES
from turtlectl.runtime.session import client_config, close_session, open_session

OPEN_TIMEOUT = 2.5  # s to reach the router before reporting "nothing to talk to"


def check_key(text: str, publish: bool = False) -> str:
    """A topic as typed by a user as a Zenoh key expression: a ROS-style leading '/' is
    dropped; anything Zenoh would refuse is BadInput.  With ``publish``, one
    plain key: no wildcards, nothing of turtlectl's own ``@`` space."""
    key = text[1:] if text.startswith("/") and len(text) > 1 else text
    try:
        key = str(zenoh.KeyExpr(key))
    except zenoh.ZError:
        raise BadInput(f"{text!r} is not a valid key expression (like robot/status or turtle1/*)") from None
    if publish and ("*" in key or "$" in key or key.startswith("@")):
        raise BadInput(f"{text!r}: publish on one plain key, without wildcards or '@'")
    return key


class NoSystem(Unreachable):
    """Nothing listens at ``connect``."""

    def __init__(self, connect: str):
        super().__init__(f"no turtlectl system at {connect} (is `turtlectl launch` running?)")
        self.connect = connect


class NotLetIn(Unreachable):
    """A router listens at ``connect`` and did not let this client in; ``reason``: what may be why."""

    def __init__(self, connect: str, reason: str):
        super().__init__(f"the router at {connect} did not let this client in within {OPEN_TIMEOUT:g} s: {reason}")
        self.connect = connect
        self.reason = reason


def _not_let_in(connect: str, logged_in: bool) -> str:
    """Why a router that is there may not have let this client in (NotLetIn's ``reason``)."""
    from turtlectl.runtime.endpoint import TLS_ENV, tls_folder

    if connect.startswith("tls/") and not tls_folder():
        why = f"a tls/ endpoint needs {TLS_ENV} naming the folder of ca.pem, client.pem, client.key"
    elif connect.startswith("tls/") and not os.path.isdir(tls_folder()):
        why = f"{TLS_ENV}={tls_folder()} is not a folder (the one `turtlectl certs` made)"
    elif connect.startswith("tls/"):
        why = f"its TLS certificate ({tls_folder()}) is not one its authority signed, or its login was refused"
    elif logged_in:
        why = "its login in the credentials file was refused (a --secure system started again makes new ones)"
    else:
        why = (
            f"a `launch --secure` system takes only clients with its login, and {credentials.where_none(connect)}; "
            "one with --tls speaks TLS only (connect with tls/HOST:PORT)"
        )
    return why


class NotPermitted(Failed):
    """A --secure system's router would drop it silently: the ``role`` may not ``verb`` on
    ``key``; ``who``: the roles that may."""

    def __init__(self, role: str, verb: str, key: str, who: list[str]):
        how = f"may: {', '.join(who)}; TURTLECTL_ROLE chooses the role" if who else "no client role may"
        super().__init__(f"not permitted: the {role} role may not {verb} {key} on this --secure system ({how})")
        self.role, self.verb, self.key, self.who = role, verb, key, who

    @property
    def said(self) -> str:
        return f"not permitted: the {self.role} role may not {self.verb} {self.key} on this --secure system"


def permitted(role: str, verb: str, key: str, goal_service: bool = False) -> bool:
    """Whether a client of ``role`` may ``verb`` (publish, call, ...) on ``key``;
    ``goal_service``: ``key`` is a goal service or its ``/cancel``, which the ``GOAL_SENDERS``
    may call (the router's rules name each one the launch's nodes serve)."""
    if goal_service and verb == "call" and role in GOAL_SENDERS:
        return True
    wanted = zenoh.KeyExpr(key)
    return any(zenoh.KeyExpr(k).includes(wanted) for k in ROLES.get(role, {}).get(verb, ()))


def who_may(verb: str, key: str, goal_service: bool = False) -> list[str]:
    return [role for role in ROLES if permitted(role, verb, key, goal_service)]


def logged_in_as(session: zenoh.Session) -> str | None:
    """The role ``session`` logged in as to a --secure system, None without a login."""
    opened = presence.of(session)
    return None if opened is None else opened.role


def domain_of(session: zenoh.Session) -> str:
    """The domain ``session`` was opened in ("" for none; the environment's for a session
    client_session did not open)."""
    opened = presence.of(session)
    return default_domain() if opened is None else opened.domain


def require(session: zenoh.Session, verb: str, key: str, goal_service: bool = False) -> None:
    """NotPermitted (exit 1) if ``session`` logged in with a role that may not ``verb``
    (publish, call, token) on ``key``: the router would drop it without a word.
    ``goal_service``: ``key`` is a goal service or its ``/cancel``, which the roles that send
    goals may call whichever node serves it (the router's rules name each one the launch's
    nodes serve)."""
    role = logged_in_as(session)
    if role is not None:
        check_permitted(role, verb, key, domain_of(session), goal_service)


def check_permitted(role: str, verb: str, key: str, domain: str, goal_service: bool = False) -> None:
    """``require``'s rule for a session of ``role`` in ``domain``: NotPermitted unless ``role`` may."""
    plain = base_key(key, domain)  # lab1/navigate_to from outside domain lab1: the rules are lab1's own
    if not permitted(role, verb, plain, goal_service):
        raise NotPermitted(role, verb, key, who_may(verb, plain, goal_service))


def _listening(connect: str) -> bool:
    """Whether something accepts TCP connections at a ``tcp/`` endpoint (True for other protocols)."""
    match = ENDPOINT_RE.match(endpoint(connect))
    if match is None or match.group(1) != "tcp":
        return True
    try:
        socket.create_connection((match.group(2).strip("[]"), int(match.group(3))), timeout=OPEN_TIMEOUT).close()
    except OSError:
        return False
    return True


def probe(connect: str) -> None:
    """Unreachable at once if nothing listens at a ``tcp/`` endpoint (Zenoh itself
    would retry for OPEN_TIMEOUT s before saying so); other protocols are left to Zenoh."""
    if not _listening(connect):
        raise NoSystem(connect)


@contextlib.contextmanager
def client_session(connect: str, domain: str | None = None, role: str | None = None) -> Iterator[zenoh.Session]:
    """A Zenoh client session to the router at ``connect``, closed (bounded) on exit; in
    ``domain`` (default: TURTLECTL_DOMAIN; "" for none); logged in as ``role`` (default:
    TURTLECTL_ROLE, else operator) when a --secure system published a login for it."""
    domain = default_domain() if domain is None else domain
    role = credentials.role() if role is None else role
    probe(connect)
    login = credentials.for_endpoint(connect, as_role=role)
    try:
        session = open_session(client_config(connect, OPEN_TIMEOUT, domain, login))
    except zenoh.ZError:
        if _listening(connect):  # a router is there and did not let this client in
            raise NotLetIn(connect, _not_let_in(connect, login is not None)) from None
        raise NoSystem(connect) from None
    try:
        # listed as a client while it is open (turtlectl list, node list); it keeps its domain and login
        presence.declare(session, domain, role if login is not None else None)
        yield session
    finally:
        with sigint_deferred():  # a Ctrl-C now must not interrupt Zenoh half-way through closing
            presence.withdraw(session)
            close_session(session)


def live_turtle_namespace(session: zenoh.Session, turtle: str) -> str:
    """The namespace turtle ``turtle``'s nodes run in on this system (messages.keys.turtle_namespace):
    its name; for turtle1, "" unless a node of namespace turtle1 is alive (then ``turtle1``, as
    any turtle's); "" for no turtle."""
    if turtle != FIRST_TURTLE:
        return turtle_namespace(turtle)
    selector = f"{NODE_TOKEN_PREFIX}/{FIRST_TURTLE}.$*/**"  # the chunk of turtle1/NAME is turtle1.NAME
    alive = any(reply.ok is not None for reply in session.liveliness().get(selector, timeout=1.0))
    return turtle_namespace(turtle, {FIRST_TURTLE} if alive else ())


def turtle_namespace_at(connect: str, turtle: str, domain: str | None = None) -> str:
    """``live_turtle_namespace`` for a command that opens its own session later: asks the router at
    ``connect`` (in ``domain``) only about turtle1 (another turtle's namespace is its name)."""
    if turtle != FIRST_TURTLE:
        return turtle_namespace(turtle)
    with client_session(connect, domain) as session:
        return live_turtle_namespace(session, turtle)


def node_of_turtle(connect: str, node: str, turtle: str, domain: str | None = None) -> str:
    """Node ``node`` as turtle ``turtle``'s nodes name it: resolved in its namespace as a key is
    (messages.keys.resolve: ``navigator`` with turtle2 is ``turtle2/navigator``, ``/sim`` is
    ``sim``); as written without a turtle."""
    return resolve(node, turtle_namespace_at(connect, turtle, domain)) if turtle else node


ROUTER_CHECK = 0.5  # s between checks that a long-running command's session still has its router


def router_lost(session: zenoh.Session) -> bool:
    """True if this client session has no router any more (the router stopped or went away)."""
    return not session.info.routers_zid()


def new_client_id() -> str:
    """An id for ``NavigateToRequest.client``: ``<pid>-<8 hex digits>``, one key chunk."""
    return f"{os.getpid()}-{secrets.token_hex(4)}"


def domain_prefix(key: str, domain: str | None = None) -> str:
    """The domain part of a key a client outside any domain (``domain`` "", default:
    TURTLECTL_DOMAIN) uses to reach into a domain (``lab1/`` in ``lab1/navigate_to``), else ""."""
    domain = default_domain() if domain is None else domain
    known = TOPICS.keys() | SERVICES.keys()
    head, slash, rest = key.partition("/")
    return head + "/" if slash and not domain and rest in known and key not in known else ""


def base_key(key: str, domain: str | None = None) -> str:
    """``key`` without the domain prefix of ``domain_prefix`` (``lab1/navigate_to`` -> ``navigate_to``)."""
    return key[len(domain_prefix(key, domain)) :]


@contextlib.contextmanager
def caller_token(session: zenoh.Session, service_key: str = NAVIGATE_TO) -> Iterator[str]:
    """Hold ``@turtlectl/client/<id>`` while the block runs and yield ``<id>``: the navigator
    cancels the goal of a caller whose token vanishes (Ctrl-C, kill -9, a timeout here).
    The token lives in the service's domain (``lab1/@turtlectl/client/<id>`` for ``lab1/navigate_to``);
    ``turtle2/navigate_to`` may also be the navigator of namespace turtle2, which follows
    ``@turtlectl/client/**`` as every navigator does: then both are held."""
    client_id = new_client_id()
    prefix = domain_prefix(service_key, domain_of(session))
    tokens = [session.liveliness().declare_token(p + client_token(client_id)) for p in dict.fromkeys([prefix, ""])]
    try:
        yield client_id
    finally:
        for token in tokens:
            token.undeclare()


def domains_on_router(connect: str) -> tuple[list[str], bool]:
    """The domains with a system on the router at ``connect`` (a supervisor's domain token, or
    nodes in the domain), and whether nodes run there outside any domain.  Asked outside
    any namespace, so it works whatever --domain this client has."""
    with client_session(connect, domain="") as session:
        found: set[str] = set()
        plain = False
        for selector in (f"{DOMAIN_TOKEN_PREFIX}/*", DOMAIN_GRAPHS, f"{NODE_TOKEN_PREFIX}/**"):
            for reply in session.liveliness().get(selector, timeout=1.0):
                if reply.ok is None:
                    continue
                key = str(reply.ok.key_expr)
                if key.startswith(NODE_TOKEN_PREFIX + "/"):
                    plain = True
                elif (domain := parse_domain_token(key)) is not None:
                    found.add(domain)
                elif "/@turtlectl/" in key:
                    found.add(key.partition("/")[0])
    return sorted(found), plain


def domain_hint(connect: str, mine: str | None = None) -> str:
    """A hint, starting with "; ", when the systems on this router run in other domains than
    this client's ``mine`` (--domain; default: TURTLECTL_DOMAIN), else "".  Never raises: it
    only adds to another error."""
    mine = default_domain() if mine is None else mine
    try:
        found, plain = domains_on_router(connect)
    except TurtlectlError:
        return ""
    others = [d for d in found if d != mine]
    if plain and mine:
        return f"; a system runs outside any domain on this router: run the command without `--domain {mine}`" + (
            f" (or use --domain {others[0]})" if others else ""
        )
    if others:
        which = ", ".join(others)
        return f"; systems run in domain{'s' * (len(others) > 1)} {which} on this router: add it before the command, `turtlectl --domain {others[0]} ...`"
    return ""


def live_graph(session: zenoh.Session, domain: str | None = None) -> Graph:
    """The live graph as this session (in ``domain``, default: the session's own) sees it.
    Outside any domain that includes every domain's graph, its names and keys prefixed with
    the domain (``lab1:sim``, ``lab1/robot/status``): tokens declared in a Zenoh namespace are ``lab1/@turtlectl/...``,
    which ``@turtlectl/**`` cannot match (Zenoh never matches a chunk starting with ``@`` by
    a wildcard), hence the second query."""
    selectors = [GRAPH] if (domain_of(session) if domain is None else domain) else [GRAPH, DOMAIN_GRAPHS]
    keys = {
        str(r.ok.key_expr) for sel in selectors for r in session.liveliness().get(sel, timeout=2.0) if r.ok is not None
    }
    current = build_graph(sorted(keys), time.time_ns())
    me = presence.of(session)
    return current if me is None else without_client(current, me.name)  # every participant but the one asking
