"""Each built-in node kind's contract is declared once (its ``Params``, ``Claims`` and ``Interface``
beside its parameters, carried by its class as a user's node class carries them) and holds
against what the node does: run on a FakeNode, it declares nothing outside its Interface
(runtime.interface refuses that), and every key its Interface names is one it declares."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any

import msgspec
import pytest

from turtlectl.messages import Reset, TeleportAbsolute, Turtles
from turtlectl.messages.keys import RESET, TELEPORT, TURTLES
from turtlectl.nodes.kinds import KINDS, NodeKind
from turtlectl.runtime.config import Interface
from turtlectl.runtime.fake import FakeNode
from turtlectl.runtime.interface import OutsideInterface

FIELDS = ("publishes", "subscribes", "serves", "calls", "watches", "goals")


def node_class(kind: NodeKind) -> Any:
    module, _, name = kind.target.partition(":")
    return getattr(importlib.import_module(module), name)


def _exercise_sim(fake: FakeNode[Any]) -> None:
    """What the simulator declares only when asked: a teleport and a reset."""
    fake.request(TELEPORT, TeleportAbsolute(x=3.0, y=3.0, theta=0.0))
    fake.request(RESET, Reset())
    fake.advance(0.1)


def _exercise_ros2_bridge(fake: FakeNode[Any]) -> None:
    """What the ROS 2 bridge declares once a turtle is there: its rows (cmd_vel both ways)."""
    fake.deliver(TURTLES, Turtles(names=["turtle1"], x=[5.5], y=[5.5], theta=[0.0]))
    fake.advance(0.1)


#: what makes a kind declare what it declares only at run time (its calls), beyond its start
EXERCISE: dict[str, Callable[[FakeNode[Any]], None]] = {"sim": _exercise_sim, "ros2_bridge": _exercise_ros2_bridge}


def run(cls: Any, kind_name: str, interface: Interface) -> None:
    """``cls`` with ``interface`` run on a FakeNode, and exercised; OutsideInterface if it declares
    something else."""
    narrowed = type(cls.__name__, (cls,), {"Interface": interface})
    with FakeNode(narrowed, name=kind_name if kind_name != "sim" else "sim") as fake:
        EXERCISE.get(kind_name, lambda _: None)(fake)
        fake.advance(0.5)


def test_a_client_kind_declares_no_entity_of_its_node():
    assert all(KINDS[name].interface == Interface() for name in CLIENT_KINDS)


@pytest.mark.parametrize("name", sorted(KINDS))
def test_the_registry_takes_each_built_in_kinds_contract_from_its_class(name):
    kind = KINDS[name]
    cls = node_class(kind)
    assert (kind.params, kind.claims, kind.interface) == (cls.Params, cls.Claims, cls.Interface)


#: the kinds whose node declares nothing of its own: the web page's traffic is its client session's
#: (its login's rights, runtime.roles), which a FakeNode cannot open; its browser tests run it
CLIENT_KINDS = ("web",)


@pytest.mark.parametrize("name", sorted(set(KINDS) - set(CLIENT_KINDS)))
def test_a_built_in_kind_declares_nothing_outside_its_interface(name):
    cls = node_class(KINDS[name])
    run(cls, name, cls.Interface)


@pytest.mark.parametrize(
    ("name", "field", "key"),
    [
        (name, field, key)
        for name, kind in sorted(KINDS.items())
        for field in FIELDS
        for key in getattr(kind.interface, field)
    ],
)
def test_every_key_a_built_in_kinds_interface_names_is_one_it_declares(name, field, key):
    """Without ``key`` in ``field``, the node declares something outside its Interface: so the
    Interface names nothing the node does not use."""
    cls = node_class(KINDS[name])
    declared: Interface = cls.Interface
    without = msgspec.structs.replace(declared, **{field: tuple(k for k in getattr(declared, field) if k != key)})
    with pytest.raises(OutsideInterface):
        run(cls, name, without)
