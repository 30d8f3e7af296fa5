"""Criterion 7 (unit part): every message type round-trips; malformed payloads are rejected clearly."""

import math

import pytest

from messages.angles import degrees_0_360, heading_degrees, heading_radians, wrap_radians


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
