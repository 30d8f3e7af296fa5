"""Which entities (publishers, subscribers, services) a router knows of now: what ``Node.claim``
checks a node's claims against, before the node declares anything."""

from __future__ import annotations

import zenoh

from turtlectl.messages.keys import ENTITY_TOKEN_PREFIX, EntityInfo, parse_entity_token
from turtlectl.runtime.config import Credentials
from turtlectl.runtime.session import client_config, close_session, open_session

#: s to hear from the router which tokens it knows
TIMEOUT = 1.0


def entities_on_router(connect: str, domain: str, credentials: Credentials | None) -> list[EntityInfo]:
    """Every entity token the router at ``connect`` knows (in ``domain``), or [] when it cannot be
    asked.  Asked through a short client session: the router knows every token and answers a
    client at once, while a peer's own liveliness get, just after opening, often answers only
    part of them (zenoh 1.10)."""
    try:
        asker = open_session(client_config(connect, TIMEOUT, domain, credentials))
    except zenoh.ZError:
        return []
    try:
        replies = asker.liveliness().get(f"{ENTITY_TOKEN_PREFIX}/**", timeout=TIMEOUT)
        tokens = [str(reply.ok.key_expr) for reply in replies if reply.ok is not None]
    finally:
        close_session(asker)
    return [entity for token in tokens if (entity := parse_entity_token(token)) is not None]
