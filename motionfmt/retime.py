"""Retime a motion: new pose times, never new values, in whole milliseconds, always strictly
increasing. :func:`scale_times` plays it faster or slower, :func:`fit_duration` makes it last a
given time, and :func:`~.fit_limits.fit_limits` stretches the segments too fast for a joint; all
three answer a :class:`Retimed`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from motiontool.errors import MotionToolError
from motiontool.motionfmt.cscan import INT_MAX

__all__ = [
    "MAX_TIME_MS",
    "Retimed",
    "Stretch",
    "TimeOverflowError",
    "fit_duration",
    "require_in_range",
    "scale_times",
]

MAX_TIME_MS = INT_MAX
"""The longest pose time a ``.motion`` file can hold, 2³¹−1 ms: Webots keeps times in a C
``int``, and ``validate`` rejects a later one (MT112)."""


@dataclass(frozen=True)
class Stretch:
    """One segment :func:`~.fit_limits.fit_limits` made longer.

    Attributes:
        segment: index of the segment (from pose ``segment`` to pose ``segment + 1``).
        old_ms, new_ms: its duration before and after, ms.
        joint: the joint that needed the most time.
        reason: ``'velocity'`` or ``'acceleration'``.
    """

    segment: int
    old_ms: int
    new_ms: int
    joint: str
    reason: str


@dataclass(frozen=True)
class Retimed:
    """New pose times and what changed.

    Attributes:
        old_times_ms, times_ms: pose times before and after, ms.
        stretches: the segments :func:`~.fit_limits.fit_limits` lengthened (empty for the
            other retimings).
        unconstrained: joints of the motion without a velocity limit (ignored by the fit).
        rounding_ms: the largest distance of a new pose time from the exact scaled time, ms
            (:func:`scale_times`, :func:`fit_duration`; 0 for :func:`~.fit_limits.fit_limits`).
    """

    old_times_ms: tuple[int, ...]
    times_ms: tuple[int, ...]
    stretches: tuple[Stretch, ...] = ()
    unconstrained: tuple[str, ...] = ()
    rounding_ms: float = 0.0

    @property
    def old_duration_ms(self) -> int:
        return self.old_times_ms[-1]

    @property
    def duration_ms(self) -> int:
        return self.times_ms[-1]

    @property
    def added_ms(self) -> int:
        """How much longer the motion became, ms (negative: shorter)."""
        return self.duration_ms - self.old_duration_ms

    @property
    def added_percent(self) -> float | None:
        """``added_ms`` as a percentage of the old duration; None for a motion of length 0."""
        if self.old_duration_ms == 0:
            return None
        return 100.0 * self.added_ms / self.old_duration_ms


class TimeOverflowError(MotionToolError):
    """A retiming would put a pose past :data:`MAX_TIME_MS`, which Webots cannot read.

    Attributes:
        last_ms: the time of the last pose it would produce, ms.
    """

    def __init__(self, last_ms: int, how: str):
        self.last_ms = last_ms
        super().__init__(
            f"{how} would put the last pose at {last_ms} ms, past the longest time a .motion file "
            f"can hold, {MAX_TIME_MS} ms (2^31-1, Webots' int)"
        )


def require_in_range(new: Sequence[int], how: str) -> None:
    """Raise :class:`TimeOverflowError` if the last of the times ``new`` (ms) is past
    :data:`MAX_TIME_MS`; ``how`` names the retiming in the message."""
    if new and new[-1] > MAX_TIME_MS:
        raise TimeOverflowError(int(new[-1]), how)


def _scaled(times: Sequence[int], num: int, den: int) -> list[int]:
    """Each time ``t`` (ms) times ``num / den`` (``den > 0``), exactly, rounded half up:
    floor(t num / den + 1/2) in integers (a Fraction per pose costs 100 times as much)."""
    two_den = 2 * den
    return [(2 * t * num + den) // two_den for t in times]


def _off(new: Sequence[int], times: Sequence[int], num: int, den: int) -> float:
    """The largest |new - t num / den| over the poses, ms (``den > 0``), computed exactly and
    rounded once."""
    from fractions import Fraction

    worst = max(abs(n * den - t * num) for n, t in zip(new, times, strict=True))
    return float(Fraction(worst, den))


def _strictly_increasing(times: list[int], last_ms: int | None = None) -> list[int]:
    """Push equal or decreasing times forward by 1 ms each; with ``last_ms``, the last time is
    fixed there and earlier times are pulled back below it instead."""
    out = list(times)
    for i in range(1, len(out)):
        out[i] = max(out[i], out[i - 1] + 1)
    if last_ms is not None and out:
        out[-1] = last_ms
        for i in range(len(out) - 2, -1, -1):
            out[i] = min(out[i], out[i + 1] - 1)
    return out


def scale_times(times_ms: Sequence[int], speed: float) -> Retimed:
    """Play ``speed`` times as fast: every pose time ``t`` becomes ``round(t / speed)`` ms.

    Times are scaled from 0 (a first pose at 200 ms moves to 400 ms at speed 0.5), rounded half
    up to whole ms; where rounding makes two poses meet (only when speeding up), the later one
    moves on by 1 ms.

    Raises:
        TimeOverflowError: a new time would be past :data:`MAX_TIME_MS`.
    """
    if not (math.isfinite(speed) and speed > 0):
        raise MotionToolError(f"the speed factor must be a positive number, got {speed}")
    old = [int(t) for t in times_ms]
    num, den = speed.as_integer_ratio()  # t / speed = t den / num, exactly
    new = _strictly_increasing(_scaled(old, den, num))
    require_in_range(new, f"retiming at speed x{speed:g}")
    return Retimed(tuple(old), tuple(new), rounding_ms=_off(new, old, den, num))


def fit_duration(times_ms: Sequence[int], duration_ms: int) -> Retimed:
    """Scale every pose time (from 0) so that the last pose is at ``duration_ms`` ms exactly.

    Raises:
        TimeOverflowError: ``duration_ms`` is past :data:`MAX_TIME_MS`.
    """
    old = [int(t) for t in times_ms]
    last = old[-1]
    require_in_range([duration_ms], f"retiming to a duration of {duration_ms} ms")
    if duration_ms < len(old) - 1 or duration_ms < 0:
        raise MotionToolError(
            f"a duration of {duration_ms} ms cannot hold {len(old)} poses at distinct whole ms; "
            f"give at least {len(old) - 1} ms"
        )
    if last == 0:
        raise MotionToolError("the motion's only pose time is 0 ms: there is no duration to scale")
    new = _strictly_increasing(_scaled(old, duration_ms, last), last_ms=duration_ms)
    return Retimed(tuple(old), tuple(new), rounding_ms=_off(new, old, duration_ms, last))
