"""Resample a motion without losing anything: put its keyframes on a uniform grid of pose times
and, with ``max_error``, remove the keyframes that the command stream does not need.

Where the grid holds every original pose time the result is *lossless*: a new keyframe lies on
its segment, so Webots' player commands the same targets at every playback time, to the last bits
of floating-point rounding in its own interpolation (see :data:`ROUNDING_RAD`). ``*`` is kept: a
new keyframe inside a segment that touches a ``*`` cell gets ``*`` too, so that segment stays
uncommanded. The document is edited losslessly (:class:`~.document.MotionDocument`): the lines
and cells it keeps keep their original spelling; new poses are spelt canonically.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.compare import MotionDiff, compare_motions
from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.player import require_held
from motiontool.motionfmt.resample_grid import Grid, GridResample

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["ROUNDING_RAD", "Resampled", "grid_times", "resample"]

ROUNDING_RAD = 1e-12
"""Floating-point slack (rad, m for linear joints) on "on the line" and "within the bound".

Webots evaluates ``v[a] + (e - t[a]) * (v[b] - v[a]) / (t[b] - t[a])`` in double precision; a
point on a segment, re-interpolated between other points of the same segment, comes out a few
units in the last place off (~1e-16 rad for joint angles of a few radians). 1e-12 rad is far
above that rounding and far below anything a motor can resolve, so ``max_error=0`` still removes
exactly collinear keyframes."""


@dataclass(frozen=True)
class Resampled:
    """What :func:`resample` did.

    Attributes:
        blocks: the result's bytes, a block at a time (anew at each call): a grid's result is
            never held whole (kept lines keep their spelling).
        n_poses, duration_ms: the result's pose count and last pose time (ms).
        step_ms: the grid step, ms, or None when only keyframes were removed.
        grid_has_keyframes: every original pose time lies on the grid (or no grid was asked).
        inserted: poses added on grid times.
        dropped_off_grid: original poses removed because their time is not on the grid.
        removed: poses removed by ``max_error`` (after the grid was applied).
        collinear: how many of ``removed`` lay on the line to within :data:`ROUNDING_RAD`.
        deviation: the result against the original, compared at every millisecond
            (:func:`~motiontool.motionfmt.compare.compare_motions`, tolerance ``max_error``
            or :data:`ROUNDING_RAD`).
        path: the original's name (the :attr:`document`'s).
    """

    blocks: Callable[[], Iterator[bytes]]
    n_poses: int
    duration_ms: int
    step_ms: int | None
    grid_has_keyframes: bool
    inserted: int
    dropped_off_grid: int
    removed: int
    collinear: int
    deviation: MotionDiff
    path: str

    @functools.cached_property
    def document(self) -> MotionDocument:
        """The result as a document, held whole (a library caller's; the CLI streams
        :attr:`blocks`)."""
        return loads(b"".join(self.blocks()), self.path)


def grid_times(first_ms: int, last_ms: int, step_ms: int) -> list[int]:
    """Multiples of ``step_ms`` between ``first_ms`` and ``last_ms`` (ms), plus both ends
    (:class:`~motiontool.motionfmt.resample_grid.Grid`, as a list).

    The ends are always kept, on the grid or not, so that the motion starts and ends when it did.
    """
    grid = Grid(first_ms, last_ms, step_ms)
    require_held(grid.count(), step_ms, "the resampling grid")
    times: list[int] = grid.between(first_ms, last_ms).tolist()
    return times


def _window_ok(
    t: npt.NDArray[np.int64],
    v: npt.NDArray[np.float64],
    a: int,
    b: int,
    t0: npt.NDArray[np.int64],
    v0: npt.NDArray[np.float64],
    bound: float,
) -> bool:
    """Whether one segment from pose ``a`` to pose ``b`` of (t, v) commands what the original
    (t0, v0) commands over ``(t[a], t[b]]``, within ``bound`` rad (:func:`_reproduce`)."""
    import numpy as np

    lo = _last_at_or_before(t0, int(t[a]))
    hi = int(np.searchsorted(t0, t[b], side="left"))  # first original pose at or after t[b]
    hi = min(hi, t0.shape[0] - 1)
    seg = v0[lo : hi + 1]
    seg_nan = np.isnan(seg[:-1]) | np.isnan(seg[1:])  # original segments lo..hi-1
    inner = slice(lo + 1, max(hi, lo + 1))
    ok = _reproduce(
        t[[a]], t[[b]], v[[a]], v[[b]],
        np.asarray(seg_nan.all(axis=0))[None], np.asarray(seg_nan.any(axis=0))[None],
        t0[None, inner], v0[None, inner], bound,
    )  # fmt: skip
    return bool(ok[0])


def _reproduce(
    ta: npt.NDArray[np.int64],
    tb: npt.NDArray[np.int64],
    va: npt.NDArray[np.float64],
    vb: npt.NDArray[np.float64],
    spans_all_nan: npt.NDArray[np.bool_],
    spans_any_nan: npt.NDArray[np.bool_],
    t_in: npt.NDArray[np.int64],
    v_in: npt.NDArray[np.float64],
    bound: float,
) -> npt.NDArray[np.bool_]:
    """The rule of a new segment, for W of them at once: whether the segment from (ta, va) to
    (tb, vb) (shapes (W,) and (W, J)) commands what the original commands over ``(ta, tb]``,
    within ``bound`` rad.

    Per joint: if an end of the new segment is ``*`` (NaN), it commands nothing, so every
    original segment it spans must touch a ``*`` (``spans_all_nan``, (W, J)); otherwise none
    may (``spans_any_nan``), and the line must stay within ``bound`` of the original at the
    original poses inside, ``t_in`` (W, K) and ``v_in`` (W, K, J): both are piecewise linear
    with corners only there, so that is where they differ most."""
    import numpy as np

    new_nan = np.isnan(va) | np.isnan(vb)
    refused = _stars_differ(new_nan, spans_all_nan, spans_any_nan)
    e = (t_in - ta[:, None]).astype(np.float64)[:, :, None]
    span = (tb - ta).astype(np.float64)[:, None, None]
    with np.errstate(invalid="ignore", over="ignore"):
        line = va[:, None, :] + e * (vb - va)[:, None, :] / span
        err = np.abs(line - v_in)
    err = np.where(new_nan[:, None, :], 0.0, err)
    within = np.all(err <= bound + ROUNDING_RAD, axis=(1, 2))  # NaN (inf cells) is False
    ok: npt.NDArray[np.bool_] = within & ~refused
    return ok


def _stars_differ(
    new_nan: npt.NDArray[np.bool_],
    spans_all_nan: npt.NDArray[np.bool_],
    spans_any_nan: npt.NDArray[np.bool_],
) -> npt.NDArray[np.bool_]:
    """Per segment (the last axis: joints), whether a new segment commands where the original
    does not, or the other way round: a joint with a ``*`` end (``new_nan``) where not every
    original segment it spans touches a ``*``, or one without where any does."""
    import numpy as np

    differ = (new_nan & ~spans_all_nan) | (~new_nan & spans_any_nan)
    return np.asarray(differ.any(axis=-1))


def _last_at_or_before(t0: npt.NDArray[np.int64], time_ms: int) -> int:
    """The last original pose at or before ``time_ms`` (the first if none): where a new
    segment starting then begins to span the original."""
    import numpy as np

    return max(int(np.searchsorted(t0, time_ms, side="right")) - 1, 0)


class _Cone:
    """What one segment from pose ``a`` of (t, v) to each later pose may do, kept up to date as
    the segment grows, so that most of :func:`_window_ok`'s answers take O(J), not a pass over
    every original pose inside (a long motion's greedy was quadratic in its length).

    Per joint, the slopes (rad/ms) a line from ``(t[a], v[a])`` may take and stay within
    ``bound`` minus a margin of every original pose inside so far (an interval: the
    intersection of one per pose), and whether the original segments spanned so far touch a
    ``*``. :meth:`surely_ok` is True only where :func:`_window_ok` is: the margin (64 units
    in the last place of the largest value) is far above the rounding of either computation.
    """

    def __init__(
        self,
        t: npt.NDArray[np.int64],
        v: npt.NDArray[np.float64],
        a: int,
        t0: npt.NDArray[np.int64],
        v0: npt.NDArray[np.float64],
        slack: float,
    ) -> None:
        import numpy as np

        self.t, self.v, self.a, self.t0, self.v0 = t, v, a, t0, v0
        self.slack = slack  # bound + rounding - margin, rad
        lo = _last_at_or_before(t0, int(t[a]))
        self.inner = lo + 1  # the next original pose to take in
        self.seg = lo  # the next original segment to take in
        joints = v.shape[1]
        self.low, self.high = np.full(joints, -np.inf), np.full(joints, np.inf)
        self.nan_any, self.nan_all = np.zeros(joints, bool), np.ones(joints, bool)

    def surely_ok(self, b: int, hi: int) -> bool:
        """Whether the segment from pose ``a`` to pose ``b`` (> a) is surely within the bound
        (False: not surely; :func:`_window_ok` decides); ``hi``: the first original pose at or
        after ``t[b]`` (the last if none). Calls go with increasing ``b``, under
        ``np.errstate(invalid="ignore")``."""
        import numpy as np

        v0, ta, va = self.v0, self.t[self.a], self.v[self.a]
        for k in range(self.seg, hi):  # original segments lo .. hi - 1
            nan = np.isnan(v0[k]) | np.isnan(v0[k + 1])
            self.nan_any |= nan
            self.nan_all &= nan
        self.seg = max(self.seg, hi)
        for k in range(self.inner, hi):  # original poses lo + 1 .. hi - 1
            dt = float(self.t0[k] - ta)
            np.fmax(self.low, (v0[k] - va - self.slack) / dt, out=self.low)
            np.fmin(self.high, (v0[k] - va + self.slack) / dt, out=self.high)
        self.inner = max(self.inner, hi)
        new_nan = np.isnan(va) | np.isnan(self.v[b])
        if _stars_differ(new_nan, self.nan_all, self.nan_any):
            return False
        slope = (self.v[b] - va) / float(self.t[b] - ta)
        return bool(((slope >= self.low) & (slope <= self.high) | new_nan).all())


def _slack(current: Motion, original: Motion, bound: float) -> float:
    """``bound`` plus the rounding slack, less a margin far above floating-point rounding in
    :func:`_window_ok` and :class:`_Cone` (64 units in the last place of the values' size)."""
    import numpy as np

    size = max(float(np.nanmax(np.abs(m.values), initial=0.0)) for m in (current, original))
    margin = 64 * np.finfo(np.float64).eps * (3 * size + bound + ROUNDING_RAD)
    return bound + ROUNDING_RAD - margin


def _simplify(
    current: Motion, original: Motion, bound: float, *, cone: bool = True
) -> tuple[list[int], int]:
    """Greedy: from each kept pose, reach as far as one segment stays within ``bound``.

    ``cone=False``: every step asks :func:`_window_ok` (the reference the tests compare with;
    quadratic in a long segment's length).

    Returns the indices of the poses to remove, and how many of them lie exactly (to within
    :data:`ROUNDING_RAD`) on the line between their two neighbours.
    """
    import numpy as np

    t, v = current.times_ms, current.values
    t0, v0 = original.times_ms, original.values
    slack = _slack(current, original, bound)
    first_after = np.minimum(np.searchsorted(t0, t, side="left"), t0.shape[0] - 1).tolist()
    n = t.shape[0]
    removed: list[int] = []
    a = 0
    with np.errstate(invalid="ignore"):
        while a < n - 1:
            b = a + 1
            reach = _Cone(t, v, a, t0, v0, slack) if cone and slack > 0 else None
            while b + 1 < n and (
                (reach is not None and reach.surely_ok(b + 1, first_after[b + 1]))
                or _window_ok(t, v, a, b + 1, t0, v0, bound)
            ):
                b += 1
            removed.extend(range(a + 1, b))
            a = b
    return removed, _collinear(t, v, np.asarray(removed, dtype=np.intp))


def _collinear(
    t: npt.NDArray[np.int64], v: npt.NDArray[np.float64], poses: npt.NDArray[np.intp]
) -> int:
    """How many of ``poses`` (each with a neighbour on both sides) lie on the line between
    their neighbours: :func:`_window_ok` of ``(i - 1, i + 1)`` against (t, v) itself with no
    bound, for all of them at once."""
    import numpy as np

    if poses.shape[0] == 0:
        return 0
    before, here, after = v[poses - 1], v[poses], v[poses + 1]
    seg_nan = (np.isnan(before) | np.isnan(here), np.isnan(here) | np.isnan(after))
    ok = _reproduce(
        t[poses - 1], t[poses + 1], before, after,
        seg_nan[0] & seg_nan[1], seg_nan[0] | seg_nan[1],
        t[poses][:, None], here[:, None, :], 0.0,
    )  # fmt: skip
    return int(ok.sum())


def resample(
    doc: MotionDocument, *, step_ms: int | None = None, max_error: float | None = None
) -> Resampled:
    """Put ``doc``'s keyframes on a grid and/or remove the keyframes the motion does not need.

    Args:
        doc: the document; it is not modified (a copy is edited).
        step_ms: grid step, ms: keyframes at every multiple of it between the first and the last
            pose time (both ends always kept). A new keyframe takes the target Webots commands
            there (``*`` inside a segment touching ``*``); an original pose whose time is not
            on the grid is removed.
        max_error: remove keyframes while every joint stays within this many rad (m for linear
            joints) of the ORIGINAL command stream, at every playback time, with the same
            commanded/uncommanded steps. 0 removes only exactly collinear keyframes.

    Returns:
        a :class:`Resampled` with the new document and the deviation it introduced.
    """
    if step_ms is None and max_error is None:
        raise MotionToolError("nothing to do: give a grid step, a maximum error, or both")
    if max_error is not None and not max_error >= 0:
        raise MotionToolError(f"the maximum error must be >= 0 rad, got {max_error}")
    original = doc.motion
    refuse_non_finite(original, doc.result, "resampling")
    out = doc.copy()
    inserted = dropped = 0
    if step_ms is not None:
        gridded = GridResample(doc, original, step_ms)
        # Streamed, its memory does not grow with it; past the cap it would take hours.
        require_held(gridded.n_poses, step_ms, "the resampling grid")
        inserted, dropped = gridded.inserted, gridded.dropped
        if max_error is None and gridded.marker_free():  # compared a window at a time
            deviation = compare_motions(original, gridded, timestep_ms=1, tolerance=ROUNDING_RAD)
            return Resampled(
                gridded.blocks, gridded.n_poses, gridded.duration_ms, step_ms, dropped == 0,
                inserted, dropped, 0, 0, deviation, doc.path,
            )  # fmt: skip
        out = loads(b"".join(gridded.blocks()), doc.path)
    removed: list[int] = []
    collinear = 0
    if max_error is not None:
        removed, collinear = _simplify(out.motion, original, max_error)
        for p in sorted(removed, reverse=True):
            out.delete_pose(p)
    tolerance = ROUNDING_RAD if max_error is None else max_error + ROUNDING_RAD
    result = out.motion
    deviation = compare_motions(original, result, timestep_ms=1, tolerance=tolerance)
    return Resampled(
        lambda: iter((out.to_bytes(),)), result.n_poses, result.duration_ms, step_ms,
        dropped == 0, inserted, dropped, len(removed), collinear, deviation, doc.path,
    )  # fmt: skip
