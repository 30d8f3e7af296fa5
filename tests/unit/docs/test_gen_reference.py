"""The generated reference pages (docs/reference/*.md) cannot drift from the code: each is what its
generator renders now, from the live Typer app, the launch file's and the kinds' Structs, and ExitCode."""

import importlib.util
from pathlib import Path

import pytest

from turtlectl.runtime.exitcodes import ExitCode

ROOT = Path(__file__).resolve().parents[3]


def _generator(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "docs" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("name", ["gen_cli", "gen_launchfile", "gen_exitcodes", "gen_api"])
def test_the_committed_page_is_what_the_generator_renders_now(name):
    gen = _generator(name)
    assert gen.OUTPUT.read_text() == gen.render(), (
        f"{gen.OUTPUT.relative_to(ROOT)} is out of date: run python docs/{name}.py"
    )


def test_every_exit_code_has_its_meaning_and_no_other():
    assert set(_generator("gen_exitcodes").MEANINGS) == set(ExitCode)


def test_the_command_reference_has_every_command_and_option_of_the_app():
    import typer

    from turtlectl.cli.main import app

    page = (ROOT / "docs" / "reference" / "cli.md").read_text()
    root = typer.main.get_command(app)
    for name, command in root.commands.items():
        assert f"`turtlectl {name}`" in page, name
        for param in command.params:
            if param.param_type_name == "option":
                assert f"`{param.opts[0]}`" in page, (name, param.opts)


def test_the_launch_file_reference_has_every_parameter_of_every_kind():
    from turtlectl.nodes.kinds import KINDS

    page = (ROOT / "docs" / "reference" / "launch-file.md").read_text()
    for kind, spec in KINDS.items():
        assert f'`run = "{kind}"`' in page
        for field in spec.params.__struct_fields__:
            assert f"`{field}" in page, (kind, field)
