"""messages.angles is the one place headings change units or get reduced."""

import math
import re
from pathlib import Path

import pytest

from turtlectl.messages.angles import (
    degrees_0_360,
    heading_degrees,
    heading_difference_degrees,
    heading_radians,
    wrap_radians,
)


@pytest.mark.parametrize(
    "degrees, reduced",
    [(1e16, 280.0), (1e308, 296.0), (-1e-17, 0.0), (360.0, 0.0), (-45.0, 315.0), (720.5, 0.5), (-1e16, 80.0)],
)
def test_headings_are_reduced_in_degrees_exactly(degrees, reduced):
    assert degrees_0_360(degrees) == pytest.approx(reduced)
    assert 0.0 <= degrees_0_360(degrees) < 360.0
    assert -math.pi <= heading_radians(degrees) < math.pi
    assert heading_radians(degrees) == pytest.approx(wrap_radians(math.radians(reduced)))


def test_radians_read_as_degrees_in_0_360():
    assert heading_degrees(-1e-18) == 0.0 and heading_degrees(-math.pi / 2) == pytest.approx(270.0)
    assert heading_degrees(2 * math.pi) == 0.0
    assert wrap_radians(math.pi) == -math.pi and wrap_radians(1e300) < math.pi


ROOT = Path(__file__).resolve().parents[3]


PACKAGES = ["messages", "runtime", "sim", "nodes", "cli"]


BY_HAND = re.compile(r"math\.degrees\(|np\.degrees\(|np\.rad2deg\(|fmod\(|%\s*360|%=\s*360")


def test_no_module_but_messages_angles_converts_or_reduces_headings():
    found = []
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            if path == ROOT / "messages" / "angles.py":
                continue
            for number, line in enumerate(path.read_text().splitlines(), 1):
                code = line.split("#", 1)[0]
                if BY_HAND.search(code):
                    found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert found == []


def test_the_check_sees_the_ways_it_names():
    for line in ("d = math.degrees(t) % 360.0", "np.degrees(a)", "math.fmod(d, 360)", "d %= 360"):
        assert BY_HAND.search(line), line


@pytest.mark.parametrize(
    "a, b, apart",
    [(179.0, -179.0, 2.0), (0.0, 180.0, 180.0), (-90.0, 90.0, 180.0), (10.0, 10.0, 0.0), (1e6, 1e6 + 30.0, 30.0)],
)
def test_heading_difference_is_in_0_180(a, b, apart):
    assert heading_difference_degrees(math.radians(a), math.radians(b)) == pytest.approx(apart)
    assert 0.0 <= heading_difference_degrees(math.radians(a), math.radians(b)) <= 180.0
