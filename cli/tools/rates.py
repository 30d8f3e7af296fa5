"""Rate statistics for ``turtlectl hz``, and when a stream has gone quiet for ``hz`` and
``echo`` (pure: no zenoh; the caller passes the time).

ros2 topic hz reports from arrival times alone, which mixes the publisher's
schedule with transport jitter; we report both the arrival view and the
publisher's own rate from the messages' ``stamp``.  A rate is over the messages of the
last SPAN seconds (at most ``--window`` of them), reported only when messages arrived
since the previous report: a topic that stops has no rate, and after SILENCE s it is
said to be silent, with its reason (cli.tools.topics), once per silence.
"""

from __future__ import annotations

import collections
import statistics

import msgspec

SILENCE = 3.0  # s without a message before echo and hz say why
SPAN = 5.0  # s: hz's rates are over the messages that arrived in the last SPAN s


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
    """One line of ``hz``: the rate of arrivals, and the publisher's from the stamps (a type
    with no stamps, such as Clock, has none to say)."""
    publisher = f" (publisher {s.publisher_rate:.3f} Hz)" if s.publisher_rate > 0 else ""
    return (
        f"{s.key}: {s.rate:.3f} Hz{publisher}, mean period {s.mean_period:.2f} ms, "
        f"jitter p50 {s.jitter_p50:.2f} / p99 {s.jitter_p99:.2f} / max {s.jitter_max:.2f} ms, window {s.samples}"
    )


class Quiet:
    """When a stream has gone quiet: ``due`` once per silence of SILENCE s, whether nothing
    ever arrived (since ``now``, the start) or a stream that flowed stopped (``flowed``)."""

    def __init__(self, now: float):
        self.last = now
        self.flowed = False
        self.told = False

    def heard(self, now: float) -> None:
        self.last, self.flowed, self.told = now, True, False

    def due(self, now: float) -> bool:
        """True once when SILENCE s have passed since the start or the last message."""
        if self.told or now - self.last < SILENCE:
            return False
        self.told = True
        return True


class _Window:
    """One topic's recent messages: (arrival s, stamp ns) of at most ``size`` of them."""

    def __init__(self, size: int, now: float):
        self.messages: collections.deque[tuple[float, int]] = collections.deque(maxlen=size)
        self.fresh = False  # messages since the previous report
        self.quiet = Quiet(now)


class Rates:
    """hz's windows of several topics: ``add`` each arrival, ``report`` every second (the
    statistics of the topics that had messages since the previous report, each over its
    last SPAN s), ``silences`` for the topics gone quiet."""

    def __init__(self, keys: list[str], size: int, now: float):
        self.windows = {key: _Window(size, now) for key in keys}

    def add(self, key: str, arrived: float, stamp: int) -> None:
        """A message on ``key`` at ``arrived`` s carrying ``stamp`` ns (0: none)."""
        window = self.windows[key]
        window.messages.append((arrived, stamp))
        window.fresh = True
        window.quiet.heard(arrived)

    def report(self, now: float) -> list[RateStats]:
        stats = []
        for key, window in self.windows.items():
            while window.messages and window.messages[0][0] < now - SPAN:
                window.messages.popleft()
            if not window.fresh:
                continue
            window.fresh = False
            arrivals = [a for a, _ in window.messages]
            st = rate_stats(key, arrivals, [s for _, s in window.messages if s])
            if st is not None:
                stats.append(st)
        return stats

    def quiet_from(self, now: float) -> None:
        """Silences count from ``now`` (the router back: each topic gets SILENCE s to resume)."""
        for w in self.windows.values():
            flowed = w.quiet.flowed
            w.quiet = Quiet(now)
            w.quiet.flowed = flowed

    def silences(self, now: float) -> list[tuple[str, bool]]:
        """The topics that went quiet by ``now`` (each once per silence), with whether
        messages had arrived on them before."""
        return [(key, w.quiet.flowed) for key, w in self.windows.items() if w.quiet.due(now)]
