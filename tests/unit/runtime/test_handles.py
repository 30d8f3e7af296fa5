"""runtime.handles and Timer.undeclare: every declaration can be withdrawn, once."""

from turtlectl.runtime.handles import Declaration
from turtlectl.runtime.node import Timer


class Part:
    def __init__(self):
        self.undeclared = 0

    def undeclare(self):
        self.undeclared += 1


def test_undeclaring_withdraws_every_part_once_and_leaves_the_nodes_list():
    owner: list[Declaration] = []
    entity, token = Part(), Part()
    declared = Declaration(owner, "subscription", "a/b")
    declared.add(entity)
    declared.add(token)
    declared.add(None)
    assert owner == [declared] and declared.active
    declared.undeclare()
    declared.undeclare()
    assert (entity.undeclared, token.undeclared) == (1, 1)
    assert owner == [] and not declared.active
    assert repr(declared) == "<subscription on a/b (undeclared)>"


def test_an_undeclared_timer_leaves_the_node_and_never_resumes():
    timers: list[Timer] = []
    t = Timer(0.1, lambda: None, start=100.0, owner=timers)
    assert timers == [t]
    t.undeclare()
    t.resume(100.5)
    assert timers == [] and not t.active
    t.undeclare()  # twice: nothing more
