"""Which steps of a motion's command stream the velocity check reads: those around each pose
time, not every step (:func:`steps_read`), as ranges of step indices merged (:func:`merged`)
and read a chunk at a time (:func:`step_times`); after an edit of the file it checked last,
those around the poses the edit changed (:class:`LastStream`, :func:`within`).

Between two poses nothing changes but the targets, each on one straight segment, so a step
there moves at its segment's speed (MT303's to judge): the findings are those of every step,
whatever the duration."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, NamedTuple

from motiontool.motionfmt.reader import NO_VALUE_MARKER

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.kinematics.checks._table import Table
    from motiontool.motionfmt.motion import Motion

__all__ = ["LastStream", "Redo", "Step", "member", "merged", "step_times", "steps_read", "within"]


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


_KEPT_POSES = 1 << 16
"""The most poses of a file whose stream findings the velocity check keeps for its next version
(:class:`LastStream`)."""

_NEAR_MARKER = 1e6
"""Values at least this large (rad, m) may meet Webots' no-value marker inside a segment (more
steps read, :func:`_marker_steps`): a file holding one is read in full."""

#: A fast controller step of one motor: (speed (unit/s), its start and end playback times (ms),
#: how many controller steps apart the two commands are).
Step = tuple[float, int, int, int]


class Redo(NamedTuple):
    """What an edit changed of the stream of the last file checked: the poses whose findings
    are found again (``first`` to ``last``), the range of steps read to find them, and how
    many poses the edit added (negative: removed)."""

    first: int
    last: int
    steps: tuple[int, int]
    shift: int


class LastStream(NamedTuple):
    """The velocity check's stream findings on the last file it checked, by (motor, pose),
    with what they were found from: an edit of that file (``motiontool server`` keeps its
    checks from one version to the next) reads the steps around the poses it changed, and
    takes the others' findings from here.

    That holds where every cell of both versions is a command (no ``*``, no ``nan``): then a
    step's target depends on the segment it is in alone (no target is held from earlier), and
    a finding on pose ``q`` on the steps from one step before pose ``q - 1`` to pose ``q``
    (:meth:`Velocity._fast_steps`), which read the poses within a few steps of them."""

    times: npt.NDArray[np.int64]
    values: npt.NDArray[np.float64]
    motors: tuple[int, ...]
    limited: tuple[int, ...]
    worst: dict[tuple[int, int], Step]

    @staticmethod
    def keeps(table: Table) -> bool:
        """Whether the findings on ``table`` can be spliced into its next version's (see the
        class doc)."""
        import numpy as np

        with np.errstate(invalid="ignore"):
            return (
                table.times.shape[0] <= _KEPT_POSES
                and bool(table.raw_defined.all())
                and bool((np.abs(table.raw) < _NEAR_MARKER).all())
            )

    def redo(self, table: Table, limited: list[int], step: int, n_steps: int) -> Redo | None:
        """What to find again on ``table``, an edit of this file (None: all of it), whose
        stream has ``n_steps`` steps of ``step`` ms, none wrapped."""
        import numpy as np

        t, n = table.times, table.times.shape[0]
        old_n = self.times.shape[0]
        if (
            self.motors != tuple(table.motors)
            or self.limited != tuple(limited)
            or self.values.shape[1] != table.raw.shape[1]
            or not self.keeps(table)
        ):
            return None
        k = min(n, old_n)
        bits, old_bits = table.raw.view(np.uint64), self.values.view(np.uint64)
        alike = (t[:k] == self.times[:k]) & (bits[:k] == old_bits[:k]).all(axis=1)
        first = int(alike.argmin()) if not alike.all() else k  # the first pose changed
        k -= first
        alike = (t[n - k :] == self.times[old_n - k :]) & (
            bits[n - k :] == old_bits[old_n - k :]
        ).all(axis=1)
        same = int(alike[::-1].argmin()) if not alike.all() else k  # the last poses alike
        end = min(n - same, n - 1)  # the first pose after the changed ones (the last if none)
        # The findings on the poses within a few steps of the changed ones are found again.
        lo = max(int(np.searchsorted(t, t[max(first - 1, 0)] - 3 * step)) - 2, 0)
        hi = min(int(np.searchsorted(t, t[end] + 3 * step, "right")) + 1, n - 1)
        start = 0 if lo < 2 else int(t[lo - 1]) // step - 2
        stop = n_steps if hi >= n - 1 else int(t[hi]) // step + 3
        return Redo(lo, hi, (max(start, 0), stop), n - old_n)

    def spliced(
        self, redo: Redo, found: dict[tuple[int, int], Step]
    ) -> dict[tuple[int, int], Step]:
        """The findings of the edited file: ``found`` on the poses found again, the others
        from here (their poses shifted by the poses the edit added)."""
        worst = {key: w for key, w in found.items() if redo.first <= key[1] <= redo.last}
        after = redo.last - redo.shift  # the last pose found again, in this file
        for (i, pose), w in self.worst.items():
            if pose < redo.first:
                worst[(i, pose)] = w
            elif pose > after:
                worst[(i, pose + redo.shift)] = w
        return worst


def within(
    lo: npt.NDArray[np.int64], hi: npt.NDArray[np.int64], steps: tuple[int, int]
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """The ranges of steps ``[lo, hi)`` (:func:`merged`) cut to ``steps`` (``[start, stop)``)."""
    import numpy as np

    start, stop = steps
    lo, hi = np.maximum(lo, start), np.minimum(hi, stop)
    keep = hi > lo
    return lo[keep], hi[keep]
