"""What every node serves about itself, whatever its kind: its parameters (read, described,
set at run time, each change told on ``turtlectl/parameter_events``), what it is (node info),
its log level, and the description of every message type it uses
(``turtlectl/types/<name>/<node>``, messages.described: how tools understand a user's type).
Declared by ``Node`` before its own code runs, as the runtime's own (``own=True``: whatever the
node's interface names, every node serves them)."""

from __future__ import annotations

import logging
import os
import socket
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import msgspec
import zenoh

from turtlectl.messages import Ack, Message, ParameterEvent, SetLogLevel, SetParameter
from turtlectl.messages.codec import register, type_name
from turtlectl.messages.described import describe as describe_type
from turtlectl.messages.keys import (
    PARAMETER_EVENTS,
    NodeDetails,
    log_level_key,
    node_key,
    param_describe_key,
    param_set_key,
    params_key,
    type_key,
)
from turtlectl.messages.params import ParamInfo
from turtlectl.runtime.config import LOG_LEVELS
from turtlectl.runtime.declarations import json_answer, publisher, service
from turtlectl.runtime.entities import Request
from turtlectl.runtime.params import ParamRefused, describe, lookup, param_infos, with_value

if TYPE_CHECKING:
    from turtlectl.runtime.node import Node


class ErrorCount(logging.Handler):
    """Counts the records at ERROR or worse that this process logs (one, on the root logger):
    what a node's details say as ``errors`` and ``last_error``."""

    def __init__(self) -> None:
        super().__init__(logging.ERROR)
        self.count = 0
        self.last = ""

    def emit(self, record: logging.LogRecord) -> None:
        self.count += 1
        try:
            self.last = record.getMessage()[:300]
        except (TypeError, ValueError):  # arguments that do not fit the format
            self.last = str(record.msg)[:300]


#: the process's count (a process may build more than one Node in tests: one count)
ERRORS = ErrorCount()


class OwnServices:
    """A node's own services, declared on ``node``'s core; ``on_params`` hooks run after a
    parameter set."""

    def __init__(self, node: Node[Any]):
        self.node = node
        self._on_params: list[Callable[[Any], None]] = []
        self._infos: list[ParamInfo] | None = None  # made at the first describe
        self._types: dict[type[Message], list[Any]] = {}  # each type it uses: [its description (JSON), when asked]
        self._queryables: list[Any] = []  # kept: a dropped queryable would go
        if ERRORS not in logging.getLogger().handlers:
            logging.getLogger().addHandler(ERRORS)
        core = node.core
        core.on_type(self.uses)  # every type the node uses, these first, is described
        json_answer(core, params_key(node.name), lambda: msgspec.json.encode(node.params), own=True)
        json_answer(core, param_describe_key(node.name), self.describe_params, own=True)
        json_answer(core, node_key(node.name), self.details, own=True)
        self._events = publisher(core, PARAMETER_EVENTS, ParameterEvent, own=True)
        service(core, param_set_key(node.name), SetParameter, Ack, self.set_param, own=True)
        service(core, log_level_key(node.name), SetLogLevel, Ack, self.set_log_level, own=True)

    def on_params(self, callback: Callable[[Any], None]) -> None:
        """Call ``callback(params)`` after each parameter set (``Node.on_params``)."""
        self._on_params.append(callback)

    def uses(self, msg_type: type[Message]) -> None:
        """The node uses ``msg_type`` (its core tells, once per type): known by its name in this
        process from now on, and its description served (made the first time it is asked for)."""
        if msg_type in self._types:
            return
        register(msg_type)  # ValueError: a second class under a name this process knows
        self._types[msg_type] = []
        key = type_key(type_name(msg_type), self.node.name)
        made = self._types[msg_type]

        def on_query(query: Any) -> None:  # Zenoh thread: made once, then read
            if not made:
                made.append(msgspec.json.encode(describe_type(msg_type)))
            query.reply(key, made[0], encoding=zenoh.Encoding.APPLICATION_JSON)

        self._queryables.append(self.node.session.declare_queryable(key, on_query))

    def details(self) -> bytes:
        level = logging.getLevelName(logging.getLogger().getEffectiveLevel())
        details = NodeDetails(
            name=self.node.name,
            pid=os.getpid(),
            host=socket.gethostname(),
            start_ns=self.node.started_ns,
            kind=self.node.kind,
            log_level=level,
            errors=ERRORS.count,
            last_error=ERRORS.last,
            use_sim_time=self.node.uses_sim_time,
        )
        return msgspec.json.encode(details)

    def describe_params(self) -> bytes:
        """``turtlectl param describe`` and ``param set``'s checks: every parameter's type, unit,
        range, default, value now and whether it can change, from the node's own Struct
        (answered on the Zenoh thread: ``self.node.params`` is read once, swapped whole)."""
        params = self.node.params
        if self._infos is None:
            self._infos = param_infos(type(params))
        return msgspec.json.encode(describe(self.node.name, self.node.kind, params, self._infos))

    def set_param(self, request: Request[SetParameter]) -> None:
        """``turtlectl param set``: validate, swap the Struct, run the hooks, tell everyone."""
        name, value = request.body.name, request.body.value
        try:
            new, old = with_value(self.node.params, name, value)
        except ParamRefused as exc:
            request.fail(f"{self.node.name}: {exc}")
            return
        self.node.params = new  # type: ignore[assignment]  # with_value keeps the Struct's type
        for callback in self._on_params:
            callback(new)
        value = lookup(msgspec.to_builtins(new), name)  # as converted: 60 -> 60.0 for a float
        self.node.log.info("parameter %s: %s -> %s", name, _shown(old), _shown(value))
        self._events.publish(ParameterEvent(node=self.node.name, name=name, old_value=old, new_value=value))
        request.respond(Ack(detail=f"{self.node.name} {name} = {_shown(value)} (was {_shown(old)})"))

    def set_log_level(self, request: Request[SetLogLevel]) -> None:
        level = request.body.level.upper()
        if level not in LOG_LEVELS:
            request.fail(f"unknown log level {request.body.level!r} (known: {', '.join(LOG_LEVELS)})")
            return
        root = logging.getLogger()
        was = logging.getLevelName(root.getEffectiveLevel())
        root.setLevel(level)
        request.respond(Ack(detail=f"{self.node.name} logs {level} and above (was {was})"))


def _shown(value: Any) -> str:
    """A parameter value as JSON text (what ``param get`` prints)."""
    return msgspec.json.encode(value).decode()
