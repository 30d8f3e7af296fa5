"""cli.tools.rates: rates and jitter from arrival times and stamps."""

import pytest

from turtlectl.cli.tools.rates import rate_stats


def test_rates_from_arrivals_and_stamps():
    arrivals = [i * 0.1 + (0.002 if i % 2 else 0.0) for i in range(11)]
    stamps = [int(i * 0.1 * 1e9) for i in range(11)]
    stats = rate_stats("k", arrivals, stamps)
    assert stats.rate == pytest.approx(10.0, rel=0.01)
    assert stats.publisher_rate == pytest.approx(10.0)
    assert stats.mean_period == pytest.approx(100.0, abs=0.3)
    assert stats.jitter_max == pytest.approx(2.0, abs=0.3)
    assert rate_stats("k", [1.0], [1]) is None


# -- a rate is over a recent window; a topic that stops goes quiet, and says so ------


def _feed(rates, key, start, stop, hz, stamped=True):
    """Messages at ``hz`` from ``start`` to ``stop`` s (fake clock), stamped with their time."""
    n = round((stop - start) * hz)
    for i in range(n):
        at = start + i / hz
        rates.add(key, at, int(at * 1e9) if stamped else 0)


def test_a_rate_is_over_the_last_seconds_and_a_stopped_topic_prints_no_rate():
    from turtlectl.cli.tools.rates import SPAN, Rates

    rates = Rates(["k"], size=1000, now=0.0)
    _feed(rates, "k", 0.0, 10.0, 10.0)
    (first,) = rates.report(10.0)
    assert first.rate == pytest.approx(10.0) and first.publisher_rate == pytest.approx(10.0)
    assert first.samples == pytest.approx(SPAN * 10, abs=1)  # the last SPAN s, not all 100
    assert rates.report(11.0) == [] and rates.report(12.0) == []  # stopped: no rate repeated
    _feed(rates, "k", 12.0, 12.0 + SPAN + 1, 2.0)  # it comes back slower
    (slower,) = rates.report(12.0 + SPAN + 1)
    assert slower.rate == pytest.approx(2.0), "the old rate does not linger in the window"


def test_the_window_holds_at_most_size_messages():
    from turtlectl.cli.tools.rates import Rates

    rates = Rates(["k"], size=10, now=0.0)
    _feed(rates, "k", 0.0, 2.0, 50.0)
    (stats,) = rates.report(2.0)
    assert stats.samples == 10 and stats.rate == pytest.approx(50.0)


def test_a_topic_is_silent_once_per_silence_and_says_whether_it_had_flowed():
    from turtlectl.cli.tools.rates import SILENCE, Rates

    rates = Rates(["a", "b"], size=100, now=0.0)
    _feed(rates, "a", 0.0, 5.0, 10.0)
    assert rates.silences(SILENCE - 0.01) == []
    assert rates.silences(SILENCE) == [("b", False)]  # b: nothing ever
    assert rates.silences(4.0) == []  # said once
    last = 4.9
    assert rates.silences(last + SILENCE - 0.01) == []
    assert rates.silences(last + SILENCE) == [("a", True)]  # a: flowed, then stopped
    assert rates.silences(last + SILENCE + 5) == []
    rates.add("a", 20.0, 0)
    rates.add("a", 20.1, 0)
    assert rates.silences(21.0) == [] and rates.silences(20.1 + SILENCE) == [("a", True)]  # once per silence


def test_quiet_is_due_once_per_silence_whether_or_not_anything_arrived():
    from turtlectl.cli.tools.rates import SILENCE, Quiet

    quiet = Quiet(now=100.0)
    assert not quiet.due(100.0 + SILENCE - 0.01)
    assert quiet.due(100.0 + SILENCE) and not quiet.flowed
    assert not quiet.due(100.0 + 2 * SILENCE)  # once
    quiet.heard(110.0)
    quiet.heard(110.1)
    assert not quiet.due(110.1 + SILENCE - 0.01)
    assert quiet.due(110.1 + SILENCE) and quiet.flowed  # a stream that stopped after flowing
    assert not quiet.due(120.0)


def test_a_type_without_stamps_says_no_publisher_rate():
    """A type without stamps shows no publisher rate (not `clock: 306.281 Hz (publisher 0.000 Hz)`)."""
    from turtlectl.cli.tools.rates import rate_line

    unstamped = rate_stats("clock", [0.0, 0.016, 0.032], [0, 0, 0])
    assert unstamped is not None and "publisher" not in rate_line(unstamped)
    stamped = rate_stats("robot/status", [0.0, 0.1, 0.2], [0, 100_000_000, 200_000_000])
    assert stamped is not None and "(publisher 10.000 Hz)" in rate_line(stamped)
