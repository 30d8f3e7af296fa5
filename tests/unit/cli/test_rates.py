"""cli.rates: rates and jitter from arrival times and stamps."""

import pytest

from cli.rates import rate_stats


def test_rates_from_arrivals_and_stamps():
    arrivals = [i * 0.1 + (0.002 if i % 2 else 0.0) for i in range(11)]
    stamps = [int(i * 0.1 * 1e9) for i in range(11)]
    stats = rate_stats("k", arrivals, stamps)
    assert stats.rate == pytest.approx(10.0, rel=0.01)
    assert stats.publisher_rate == pytest.approx(10.0)
    assert stats.mean_period == pytest.approx(100.0, abs=0.3)
    assert stats.jitter_max == pytest.approx(2.0, abs=0.3)
    assert rate_stats("k", [1.0], [1]) is None
