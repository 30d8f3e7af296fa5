"""docs/interfaces.md cannot drift from the wire contract: it is generated from messages/
(docs/gen_interfaces.py), and every field and key must be documented with a unit."""

import importlib.util
from pathlib import Path

import msgspec
import pytest

from turtlectl.messages import ALL_TYPES, keys

ROOT = Path(__file__).resolve().parents[3]


def _generator():
    spec = importlib.util.spec_from_file_location("gen_interfaces", ROOT / "docs" / "gen_interfaces.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


gen = _generator()


DOC = (ROOT / "docs" / "interfaces.md").read_text()


def test_the_committed_reference_is_what_the_generator_renders_now():
    assert DOC == gen.render(), "docs/interfaces.md is out of date: run python docs/gen_interfaces.py"


@pytest.mark.parametrize("msg_type", ALL_TYPES, ids=lambda t: t.__name__)
def test_every_field_of_every_type_has_a_unit_range_and_meaning(msg_type):
    fields = {f.name for f in msgspec.inspect.type_info(msg_type).fields}
    documented = gen.FIELDS.get(msg_type.__name__)
    assert documented is not None, f"{msg_type.__name__} is not in messages/reference.py FIELDS"
    assert set(documented) == fields, (
        f"{msg_type.__name__}: undocumented {fields - set(documented)}, stale {set(documented) - fields}"
    )
    for name, (unit, span, meaning) in documented.items():
        assert unit and span and meaning, (msg_type.__name__, name)
        assert f"| `{name}` |" in DOC.split(f"### {msg_type.__name__}\n", 1)[1].split("\n### ", 1)[0]


def test_no_documented_type_is_gone():
    assert set(gen.FIELDS) == {t.__name__ for t in ALL_TYPES}


def test_every_key_and_token_is_documented_with_its_type():
    for key, msg_type in keys.TOPICS.items():
        assert gen.KEYS[key][:2] == ("topic", msg_type.__name__), key
    for key, (request, response) in keys.SERVICES.items():
        kind, payload = gen.KEYS[key][:2]
        assert kind == "service" and payload.startswith(f"{request.__name__} -> ") and response.__name__ in payload, key
    for key in (keys.WORLD_KEY, keys.params_key("<node>")):
        assert gen.KEYS[key][0] == "queryable"
    prefixes = [v for k, v in vars(keys).items() if k.endswith("_PREFIX") and isinstance(v, str)]
    assert len(prefixes) >= 4
    for prefix in prefixes:
        assert any(k.startswith(prefix + "/") and gen.KEYS[k][0] == "liveliness token" for k in gen.KEYS), prefix
    for key in gen.KEYS:
        assert f"| `{key}` |" in DOC


def test_the_node_token_documented_is_the_one_nodes_declare():
    token = keys.node_token(keys.NodeInfo(name="sim", pid=12, host="box", start_ns=34))
    assert token == "@turtlectl/node/sim/12/box/34"
    assert "`@turtlectl/node/<name>/<pid>/<host>/<start_ns>`" in DOC


def test_the_worked_example_is_in_the_reference_whole():
    assert (ROOT / "docs" / "examples" / "raw_client.py").read_text().rstrip() in DOC
