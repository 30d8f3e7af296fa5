"""The page's frames: what a browser may send, how a bad one is refused, and what each role's page may do."""

from __future__ import annotations

import json

import pytest

from turtlectl.cli.web import protocol
from turtlectl.cli.web.protocol import BadFrame, Drive, Goal, SetParam, Spawn, Stop, Watch, can, parse, refusal


def frame(**fields: object) -> str:
    return json.dumps(fields)


def test_a_goal_parses_with_its_units() -> None:
    got = parse(frame(t="goal", turtle="turtle2", x=8, y=3.5, theta=90, id=4))
    assert got == Goal(id=4, turtle="turtle2", x=8.0, y=3.5, theta=90.0)


def test_every_kind_the_docstring_names_parses() -> None:
    samples = {
        "goal": {"turtle": "t", "x": 1, "y": 1, "theta": 0},
        "cancel": {"turtle": "t"},
        "teleport": {"turtle": "t", "x": 1, "y": 1, "theta": 0},
        "spawn": {"x": 1, "y": 1, "theta": 0},
        "kill": {"turtle": "t"},
        "drive": {"turtle": "t", "linear": 1, "angular": 0},
        "stop": {"turtle": "t"},
        "watch": {"keys": ["robot/status"]},
        "params": {"node": "navigator"},
        "set_param": {"node": "navigator", "name": "goal_timeout", "value": "60"},
    }
    assert set(samples) == set(protocol.KINDS)
    for kind, fields in samples.items():
        assert f"``{kind}``" in protocol.__doc__
        parse(frame(t=kind, **fields))


@pytest.mark.parametrize(
    ("data", "said"),
    [
        ("garbage", "not JSON"),
        (frame(t="fly", turtle="t"), "unknown frame kind"),
        (frame(turtle="t"), "unknown frame kind"),
        (frame(t="goal", turtle="t", x="8", y=1, theta=0), "Expected `float`, got `str` - at `$.x`"),
        (frame(t="goal", turtle="t", x=1, y=1), "missing required field `theta`"),
        (frame(t="stop", turtle="t", speed=3), "unknown field `speed`"),
        ('{"t": "drive", "turtle": "t", "linear": NaN, "angular": 0}', "not JSON"),
        (frame(t="watch", keys=[f"k{i}" for i in range(protocol.WATCH_LIMIT + 1)]), "at most 16"),
        ("x" * (protocol.MAX_FRAME + 1), "at most"),
    ],
)
def test_a_bad_frame_is_refused_in_one_line(data: str, said: str) -> None:
    with pytest.raises(BadFrame) as refused:
        parse(data)
    assert said in str(refused.value)
    assert "\n" not in str(refused.value)


def test_an_infinite_speed_is_refused() -> None:
    with pytest.raises(BadFrame, match="out of range|finite"):
        parse('{"t": "drive", "turtle": "t", "linear": 1e999, "angular": 0}')


def test_without_secure_a_page_may_do_everything() -> None:
    assert can("viewer", secure=False) == protocol.Can(True, True, True)


def test_each_role_may_do_what_its_login_may() -> None:
    assert can("viewer", True) == protocol.Can(drive=False, command=False, edit=False)
    assert can("operator", True) == protocol.Can(drive=False, command=True, edit=True)
    assert can("teleop", True) == protocol.Can(drive=True, command=True, edit=True)


def test_a_viewer_is_told_which_role_may() -> None:
    viewer = can("viewer", True)
    drive = Drive(turtle="turtle1", linear=1.0, angular=0.0)
    assert "--role teleop" in refusal("viewer", drive, viewer)
    assert "--role teleop" in refusal("viewer", Stop(turtle="turtle1"), viewer)
    assert "--role operator" in refusal("viewer", Spawn(x=1, y=1, theta=0), viewer)
    assert "--role operator" in refusal("viewer", SetParam(node="n", name="p", value="1"), viewer)
    assert refusal("viewer", Watch(keys=["robot/status"]), viewer) == ""  # watching is every role's
    assert refusal("teleop", drive, can("teleop", True)) == ""


def test_a_scan_with_no_hit_is_null_in_json() -> None:
    assert json.loads(protocol.encode("frame", ranges=[1.0, float("inf")])) == {"t": "frame", "ranges": [1.0, None]}
