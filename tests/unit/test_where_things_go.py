"""docs/explanation/architecture.md's "Where a new thing goes", shown: a new command and a new node
kind are each one file (a new declaration kind is too: tests/unit/runtime/test_core.py declares
one), and each goes through the same path as the built-ins."""

from __future__ import annotations

import textwrap
from pathlib import Path

import typer
from typer.testing import CliRunner

from turtlectl.messages import Twist


def test_a_new_command_is_one_function_registered_by_its_group_module():
    """A command raises a turtlectl.Error; cli.main makes its message and exit code (the one place)."""
    from turtlectl.cli import main
    from turtlectl.runtime.client.errors import BadInput

    # what a group module of cli/commands/ holds: the command, thin, and its registration
    def wave(times: int = typer.Argument(..., help="How many waves.")) -> None:
        """Wave TIMES times."""
        if times < 1:
            raise BadInput(f"wave: TIMES must be at least 1 (got {times})")
        typer.echo("~" * times)

    def register(app: typer.Typer) -> None:
        app.command()(wave)

    register(main.app)
    try:
        runner = CliRunner()
        ran = runner.invoke(main.app, ["wave", "3"])
        assert (ran.exit_code, ran.stdout) == (0, "~~~\n")
        shown = runner.invoke(main.app, ["--help"])
        assert "wave" in shown.stdout  # listed under "Other" until COMMAND_GROUPS names its group
        assert main.error_line(BadInput("wave: TIMES must be at least 1 (got 0)")).startswith("turtlectl: error: wave:")
        refused = runner.invoke(main.app, ["wave", "0"])
        assert isinstance(refused.exception, BadInput) and refused.exception.exit_code == 2
    finally:
        main.app.registered_commands[:] = [c for c in main.app.registered_commands if c.callback is not wave]


BEACON = '''
    """A beacon: publishes a zero Twist on ``beacon`` every ``period`` s."""

    import msgspec

    from turtlectl import Interface, Node
    from turtlectl.messages import Twist


    class BeaconParams(msgspec.Struct, forbid_unknown_fields=True):
        period: float = 0.5  # s: between two messages


    class Beacon:
        Params = BeaconParams
        Interface = Interface(publishes=("beacon",))  # what it may declare: checked as it declares

        def __init__(self, node: Node[BeaconParams]):
            self.pub = node.publisher("beacon", Twist)
            node.timer(node.params.period, lambda: self.pub.publish(Twist()))
'''


def test_a_new_node_kind_is_one_file(tmp_path: Path):
    """The file's class carries its parameters and interface; kind_of reads it as it reads a
    built-in's, and it runs on the real node runtime (FakeNode) with its interface enforced."""
    from turtlectl.nodes.kinds import kind_of
    from turtlectl.runtime.fake import FakeNode
    from turtlectl.runtime.loader import load

    (tmp_path / "beacon.py").write_text(textwrap.dedent(BEACON))
    kind = kind_of("./beacon.py:Beacon", tmp_path)
    assert kind.params.__name__ == "BeaconParams" and kind.interface is not None
    assert kind.interface.publishes == ("beacon",)
    cls, _ = load("./beacon.py:Beacon", tmp_path)
    with FakeNode(cls, {"period": 0.25}) as fake:
        fake.advance(1.0)
        assert len(fake.published("beacon")) == 4
        assert all(isinstance(m, Twist) for m in fake.published("beacon"))
