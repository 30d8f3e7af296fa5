"""The message types a tool understands: the built-ins, and any other it learns, on first
meeting it, from the nodes that use it (each serves ``turtlectl/types/<name>/<node>``, the
type's description: messages.described).  A learnt type is rebuilt as a class
(``struct_from``) and known by name in this process from then on, so every tool decodes,
shows and validates it as a built-in.  Two nodes describing one name differently are a
conflict, kept with who said what."""

from __future__ import annotations

import time
from typing import Any

import msgspec
import zenoh

from turtlectl.messages import Message
from turtlectl.messages.codec import TYPES_BY_NAME, register
from turtlectl.messages.described import DescriptionError, TypeDescription, describable, struct_from
from turtlectl.messages.keys import type_from_chunk, type_key

ASK_TIMEOUT = 2.0  # s: how long the nodes have to describe a type
RETRY = 5.0  # s: an undescribed type is asked about again after this (its node may start meanwhile)


def descriptions(session: zenoh.Session, name: str = "*") -> dict[str, dict[str, TypeDescription]]:
    """What the nodes now running say of type ``name`` (``*``: of every type in use): type
    name -> node -> description.  Replies that do not read as a description are left out."""
    found: dict[str, dict[str, TypeDescription]] = {}
    replies = session.get(
        type_key(name, "*"),
        target=zenoh.QueryTarget.ALL,
        consolidation=zenoh.ConsolidationMode.NONE,
        timeout=ASK_TIMEOUT,
    )
    for reply in replies:
        if reply.ok is None:
            continue
        parts = str(reply.ok.key_expr).split("/")
        try:
            described = msgspec.json.decode(reply.ok.payload.to_bytes(), type=TypeDescription)
        except msgspec.DecodeError:
            continue
        found.setdefault(type_from_chunk(parts[-2]), {})[parts[-1]] = described
    return found


class TypeBook:
    """The types one session's tool has met; ``resolve`` learns one the first time."""

    def __init__(self, session: zenoh.Session):
        self.session = session
        self.described: dict[str, dict[str, TypeDescription]] = {}  # name -> node -> what it said
        self.asked: dict[str, float] = {}  # undescribed name -> when last asked (not again before RETRY s)
        self._variants: dict[str, list[type[Message]]] = {}  # a conflicting name's other classes

    def resolve(self, name: str) -> type[Message] | None:
        """The class of type ``name``: known (a built-in, or learnt), else learnt now from the
        nodes that use it; None if none describes it (asked again after RETRY s)."""
        known = TYPES_BY_NAME.get(name)
        if known is not None:
            return known
        if not describable(name):  # a raw encoding may name anything (a//b, **): no key to ask on
            return None
        asked = self.asked.get(name)
        if asked is not None and time.monotonic() - asked < RETRY:
            return None
        said = descriptions(self.session, name).get(name, {})
        self.asked[name] = time.monotonic()
        return self.learn(name, said)

    def learn_all(self) -> dict[str, dict[str, TypeDescription]]:
        """Every type the running nodes use, learnt at once (one query); what they said."""
        said = descriptions(self.session)
        for name, by_node in said.items():
            if name not in TYPES_BY_NAME:
                self.learn(name, by_node)
        return said

    def learn(self, name: str, said: dict[str, TypeDescription]) -> type[Message] | None:
        """Learn type ``name`` from what the nodes ``said`` of it (node -> description): its class,
        registered (another class per other description kept for ``conflict``); None if nobody
        described it or a description is unusable."""
        if not said:
            return None
        self.described[name] = said
        first = next(iter(said.values()))
        others = {d.hash: d for d in said.values() if d.hash != first.hash}  # one name, other types
        try:
            self._variants[name] = [struct_from(d) for d in others.values()]
            known = TYPES_BY_NAME.get(name)  # learnt already in this process (another book)
            return known if known is not None else register(struct_from(first))
        except DescriptionError:
            return None

    def variants(self, name: str) -> list[type[Message]]:
        """The other classes of a name the nodes describe more than one way (none: [])."""
        return self._variants.get(name, [])

    def conflict(self, name: str) -> str:
        """Who describes ``name`` how, when they disagree ('' when they agree or it is unknown)."""
        said = self.described.get(name, {})
        return f"{name} is {conflict(said)}" if conflict(said) else ""


def conflict(said: dict[str, TypeDescription]) -> str:
    """``described 2 ways: a1b2c3d4 by follower, e5f6a7b8 by mapper`` when the nodes' descriptions
    of one type name differ ('' when they agree)."""
    hashes = {d.hash for d in said.values()}
    if len(hashes) < 2:
        return ""
    ways = ", ".join(f"{d.hash.removeprefix('TH01_')[:8]} by {node}" for node, d in sorted(said.items()))
    return f"described {len(hashes)} ways: {ways}"


def conflicts(session: zenoh.Session) -> list[str]:
    """Every type name the running nodes describe differently, each with who says what."""
    return [f"{name} is {conflict(said)}" for name, said in sorted(descriptions(session).items()) if conflict(said)]


def generic(payload: bytes, encoding: str) -> Any:
    """A payload no description explains, decoded as what it is (msgpack or JSON), or None."""
    decoder = msgspec.json.decode if encoding.startswith("application/json") else msgspec.msgpack.decode
    try:
        return decoder(payload)
    except msgspec.DecodeError:
        return None
