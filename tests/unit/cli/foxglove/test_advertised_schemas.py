"""The JSON Schemas turtlectl advertises (in recordings and on the Foxglove server) say what it
accepts: a client that validates its request first is not refused the README's own examples,
and every message without its ``type`` tag (decoding a known type accepts it absent)."""

from __future__ import annotations

import json

import pytest

jsonschema = pytest.importorskip("jsonschema")

from tests.unit.messages.samples import SAMPLES  # noqa: E402
from turtlectl.cli.foxglove.bridge import SERVICES, _message_schema  # noqa: E402
from turtlectl.messages import Cancel, NavigateToRequest, Reset, TeleportAbsolute, decode_any, encode  # noqa: E402
from turtlectl.messages.jsonform import from_json, json_schema, to_json  # noqa: E402

README_REQUESTS = [  # README: `turtlectl call ...` and the Foxglove section
    (NavigateToRequest, {"x": 8, "y": 5, "theta": 90}),
    (TeleportAbsolute, {"x": 2, "y": 2, "theta": 0}),
    (Reset, {}),  # "No fields: the map is {"type": "Reset"} (or empty)"
    (Cancel, {}),
]


def _valid(schema: dict, document: object) -> bool:
    return jsonschema.Draft202012Validator(schema).is_valid(document)


@pytest.mark.parametrize(("request_type", "example"), README_REQUESTS, ids=lambda x: getattr(x, "__name__", ""))
def test_the_readmes_requests_satisfy_the_schemas_the_foxglove_server_advertises(request_type, example):
    (advertised,) = [_message_schema(req) for req, _, _ in SERVICES.values() if req is request_type]
    schema = json.loads(advertised.schema.data)
    assert _valid(schema, example), schema.get("required")
    assert _valid(schema, {"type": request_type.__struct_config__.tag, **example})  # the tag may be given
    assert not _valid(schema, {"type": "Pose", **example})  # but not another type's
    from_json(json.dumps(example).encode(), request_type)  # and the server accepts it


def test_every_service_request_schema_leaves_the_tag_optional():
    for request_type, _, _ in SERVICES.values():
        schema = json.loads(_message_schema(request_type).schema.data)
        assert "type" not in schema.get("required", []), request_type.__name__


@pytest.mark.parametrize("msg", SAMPLES, ids=lambda m: type(m).__name__)
def test_every_message_without_its_tag_is_valid_as_it_is_accepted(msg):
    msg = decode_any(encode(msg))
    schema = json_schema(type(msg))
    document = json.loads(to_json(msg))
    assert _valid(schema, document)
    del document["type"]
    assert _valid(schema, document)
    assert encode(from_json(json.dumps(document).encode(), type(msg))) == encode(msg)


def test_a_request_missing_a_required_field_is_still_invalid():
    schema = json_schema(NavigateToRequest)
    assert not _valid(schema, {"x": 8, "y": 5})
    assert not _valid(schema, {"x": 8, "y": 5, "theta": 90, "speed": 1})
