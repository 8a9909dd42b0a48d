"""Which steps of a motion's command stream the velocity check reads: those around each pose
time, not every step (:func:`steps_read`), as ranges of step indices merged (:func:`merged`)
and read a chunk at a time (:func:`step_times`).

Between two poses nothing changes but the targets, each on one straight segment, so a step
there moves at its segment's speed (MT303's to judge): the findings are those of every step,
whatever the duration."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

from motiontool.motionfmt.reader import NO_VALUE_MARKER

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["member", "merged", "step_times", "steps_read"]


def steps_read(
    motion: Motion, step: int, n_steps: int
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """The steps of the command stream the check reads, as ranges ``[lo, hi)`` of step
    indices (step ``s`` at ``s * step`` ms; ``n_steps`` steps, none wrapped), possibly
    overlapping: the two steps on either side of each pose time, the first and last two, and
    those around a target exactly equal to Webots' no-value marker inside a segment.

    Between two such steps nothing changes but the targets: the same columns send, each a
    target on one straight segment (Webots' player interpolates every step of a segment with
    one expression, correctly rounded, so monotone), so a target moves at its segment's speed
    at every step. A step faster than the maximum velocity there is on a segment MT303 reports,
    whose steps MT304 leaves to it: the findings are those of every step, whatever the
    duration (a 3-line file ending at 2147483647 ms has 107 million 20 ms steps).
    """
    import numpy as np

    around = motion.times_ms // step  # (np.unique would import numpy.ma)
    lo = np.concatenate([around - 1, [0, n_steps - 2], *_marker_steps(motion, step, n_steps)])
    return np.clip(lo, 0, n_steps), np.clip(lo + 4, 0, n_steps)


def _marker_steps(motion: Motion, step: int, n_steps: int) -> list[npt.NDArray[np.int64]]:
    """Where a target inside a segment (a column's number at both ends) comes out exactly
    equal to Webots' no-value marker, so that it is not sent: the first step of each such
    stretch of steps and the first after it, less two (``lo`` of :func:`steps_read`'s ranges
    around them). A target is monotone along its segment, so the stretch is one, found by
    bisection (O(log steps)), every segment at once."""
    import numpy as np

    t, v, c = motion.times_ms, motion.values, motion.commanded
    if t.shape[0] < 2:
        return []
    a, b = v[:-1], v[1:]
    marker = NO_VALUE_MARKER
    with np.errstate(invalid="ignore"):
        through = (np.fmin(a, b) <= marker) & (marker <= np.fmax(a, b)) & ((a != b) | (a != marker))
    segs, cols = np.nonzero(c[:-1] & c[1:] & through)
    first = np.maximum(t[segs] // step + 1, 1)  # the steps inside (t[seg], t[seg + 1]]
    end = np.minimum(t[segs + 1] // step, n_steps - 1) + 1
    v0, v1, t0 = a[segs, cols], b[segs, cols], t[segs]
    dt = (t[segs + 1] - t0).astype(np.float64)
    rising = v1 > v0

    def bisect(
        past: Callable[[npt.NDArray[np.float64]], npt.NDArray[np.bool_]],
    ) -> npt.NDArray[np.int64]:
        """The first step of each segment whose target is ``past`` the marker, else ``end``."""
        lo, hi = first.copy(), end.copy()
        while (open_ := lo < hi).any():
            mid = (lo + hi) // 2
            with np.errstate(all="ignore"):  # commands_at's expression: inf - inf is NaN
                target = (v1 - v0) * (mid * step - t0).astype(np.float64) / dt + v0
            now = past(target)
            hi = np.where(open_ & now, mid, hi)
            lo = np.where(open_ & ~now, mid + 1, lo)
        return lo

    at = bisect(lambda q: np.where(rising, q >= marker, q <= marker))
    beyond = bisect(lambda q: np.where(rising, q > marker, q < marker))
    return [at - 2, beyond - 2]


def merged(
    lo: npt.NDArray[np.int64], hi: npt.NDArray[np.int64]
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """The ranges ``[lo, hi)`` merged where they overlap or touch: sorted, disjoint, apart."""
    import numpy as np

    keep = hi > lo
    lo, hi = lo[keep], hi[keep]
    order = np.argsort(lo, kind="stable")
    lo, hi = lo[order], np.maximum.accumulate(hi[order])
    start = np.flatnonzero(np.concatenate([[True], lo[1:] > hi[:-1]]))
    return lo[start], hi[np.append(start[1:], lo.shape[0]) - 1]


def step_times(
    lo: npt.NDArray[np.int64], hi: npt.NDArray[np.int64], step: int, size: int
) -> Iterator[npt.NDArray[np.int64]]:
    """The times (ms) of the steps of the ranges ``[lo, hi)`` (:func:`merged`), in order, at
    most ``size`` at a time."""
    import numpy as np

    ends = np.cumsum(hi - lo)
    total = int(ends[-1]) if ends.shape[0] else 0
    for first in range(0, total, size):
        k = np.arange(first, min(first + size, total), dtype=np.int64)
        r = np.searchsorted(ends, k, side="right")  # the range of the k-th step read
        yield (lo[r] + k - (ends[r] - (hi[r] - lo[r]))) * step


def member(x: npt.NDArray[np.int64], sorted_values: npt.NDArray[np.int64]) -> npt.NDArray[np.bool_]:
    """Whether each of ``x`` is one of ``sorted_values`` (sorted, not empty)."""
    import numpy as np

    at = np.minimum(np.searchsorted(sorted_values, x), sorted_values.shape[0] - 1)
    found: npt.NDArray[np.bool_] = sorted_values[at] == x
    return found
