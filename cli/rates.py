"""Rate statistics for ``turtlectl hz`` (pure: no zenoh, no clock).

ros2 topic hz reports from arrival times alone, which mixes the publisher's
schedule with transport jitter; we report both the arrival view and the
publisher's own rate from the messages' ``stamp``.
"""

from __future__ import annotations

import statistics

import msgspec


class RateStats(msgspec.Struct):
    """key: the topic.  samples: messages in the window.  rate: Hz from arrivals.
    mean_period: ms.  jitter_p50/p99/max: ms, |period - mean period| at arrival.
    publisher_rate: Hz from the messages' stamps (0 when they carry none)."""

    key: str
    samples: int
    rate: float
    mean_period: float
    jitter_p50: float
    jitter_p99: float
    jitter_max: float
    publisher_rate: float


def _percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q / 100.0 * (len(ordered) - 1)))]


def rate_stats(key: str, arrivals: list[float], stamps: list[int]) -> RateStats | None:
    """Statistics over a window: ``arrivals`` in s (monotonic), ``stamps`` in ns; None below 2 samples."""
    if len(arrivals) < 2:
        return None
    periods = [b - a for a, b in zip(arrivals, arrivals[1:], strict=False)]
    mean = statistics.fmean(periods)
    jitter = [abs(p - mean) * 1e3 for p in periods]
    span_ns = stamps[-1] - stamps[0] if len(stamps) >= 2 else 0
    return RateStats(
        key=key,
        samples=len(arrivals),
        rate=(len(arrivals) - 1) / (arrivals[-1] - arrivals[0]) if arrivals[-1] > arrivals[0] else 0.0,
        mean_period=mean * 1e3,
        jitter_p50=_percentile(jitter, 50),
        jitter_p99=_percentile(jitter, 99),
        jitter_max=max(jitter),
        publisher_rate=(len(stamps) - 1) / (span_ns / 1e9) if span_ns > 0 else 0.0,
    )


def rate_line(s: RateStats) -> str:
    return (
        f"{s.key}: {s.rate:.3f} Hz (publisher {s.publisher_rate:.3f} Hz), mean period {s.mean_period:.2f} ms, "
        f"jitter p50 {s.jitter_p50:.2f} / p99 {s.jitter_p99:.2f} / max {s.jitter_max:.2f} ms, window {s.samples}"
    )
