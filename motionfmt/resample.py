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

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.compare import MotionDiff, compare_motions
from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.player import require_held, targets_at

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
        document: the edited document (kept lines keep their spelling).
        step_ms: the grid step, ms, or None when only keyframes were removed.
        grid_has_keyframes: every original pose time lies on the grid (or no grid was asked).
        inserted: poses added on grid times.
        dropped_off_grid: original poses removed because their time is not on the grid.
        removed: poses removed by ``max_error`` (after the grid was applied).
        collinear: how many of ``removed`` lay on the line to within :data:`ROUNDING_RAD`.
        deviation: the result against the original, compared at every millisecond
            (:func:`~motiontool.motionfmt.compare.compare_motions`, tolerance ``max_error``
            or :data:`ROUNDING_RAD`).
    """

    document: MotionDocument
    step_ms: int | None
    grid_has_keyframes: bool
    inserted: int
    dropped_off_grid: int
    removed: int
    collinear: int
    deviation: MotionDiff


def grid_times(first_ms: int, last_ms: int, step_ms: int) -> list[int]:
    """Multiples of ``step_ms`` between ``first_ms`` and ``last_ms`` (ms), plus both ends.

    The ends are always kept, on the grid or not, so that the motion starts and ends when it did.
    """
    if step_ms <= 0:
        raise MotionToolError(f"the grid step must be a positive number of ms, got {step_ms}")
    start = -(-first_ms // step_ms) * step_ms
    require_held(max(0, (last_ms - start) // step_ms + 1), step_ms, "the resampling grid")
    return sorted({first_ms, last_ms, *range(start, last_ms + 1, step_ms)})


def _pose_name(time_ms: int) -> str:
    return f"Pose{time_ms}ms"


def _apply_grid(doc: MotionDocument, original: Motion, grid: Sequence[int]) -> tuple[int, int]:
    """Delete poses off ``grid``, insert the grid times the document lacks; (inserted, dropped)."""
    import numpy as np

    on_grid = set(grid)
    times = [int(t) for t in original.times_ms]
    dropped = 0
    for p in range(len(times) - 1, -1, -1):
        if times[p] not in on_grid:
            doc.delete_pose(p)
            del times[p]
            dropped += 1
    have = set(times)
    new = [t for t in grid if t not in have]
    at = np.searchsorted(np.asarray(times, dtype=np.int64), new).tolist()
    values = targets_at(original, np.asarray(new, dtype=np.int64))
    doc.insert_poses(at, new, [_pose_name(t) for t in new], values)
    return len(new), dropped


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
    (t0, v0) commands over ``(t[a], t[b]]``, within ``bound`` rad.

    Per joint: if an end of the new segment is ``*``, the new segment commands nothing, so every
    original segment it spans must touch a ``*``; otherwise none may, and the line must stay
    within ``bound`` of the original at the original pose times inside (both are piecewise linear
    with corners only there, so that is where they differ most).
    """
    import numpy as np

    ta, tb = t[a], t[b]
    lo = int(np.searchsorted(t0, ta, side="right")) - 1  # last original pose at or before ta
    hi = int(np.searchsorted(t0, tb, side="left"))  # first original pose at or after tb
    lo, hi = max(lo, 0), min(hi, t0.shape[0] - 1)
    seg = v0[lo : hi + 1]
    seg_nan = np.isnan(seg[:-1]) | np.isnan(seg[1:])  # original segments lo..hi-1
    new_nan = np.isnan(v[a]) | np.isnan(v[b])
    if np.any(new_nan & ~seg_nan.all(axis=0)) or np.any(~new_nan & seg_nan.any(axis=0)):
        return False
    inner = slice(lo + 1, hi)
    if hi <= lo + 1:
        return True
    e = (t0[inner] - ta).astype(np.float64)[:, None]
    with np.errstate(invalid="ignore", over="ignore"):
        line = v[a] + e * (v[b] - v[a]) / float(tb - ta)
        err = np.abs(line - v0[inner])
    err = np.where(new_nan[None, :], 0.0, err)
    return bool(np.all(err <= bound + ROUNDING_RAD))  # NaN (inf cells) compares False


def _simplify(current: Motion, original: Motion, bound: float) -> tuple[list[int], int]:
    """Greedy: from each kept pose, reach as far as one segment stays within ``bound``.

    Returns the indices of the poses to remove, and how many of them lie exactly (to within
    :data:`ROUNDING_RAD`) on the line between their two neighbours.
    """
    t, v = current.times_ms, current.values
    t0, v0 = original.times_ms, original.values
    n = t.shape[0]
    removed: list[int] = []
    a = 0
    while a < n - 1:
        b = a + 1
        while b + 1 < n and _window_ok(t, v, a, b + 1, t0, v0, bound):
            b += 1
        removed.extend(range(a + 1, b))
        a = b
    collinear = sum(_window_ok(t, v, i - 1, i + 1, t, v, 0.0) for i in removed)
    return removed, collinear


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
    out = loads(doc.to_bytes(), doc.path)
    inserted = dropped = 0
    grid_has_keyframes = True
    if step_ms is not None:
        grid = grid_times(int(original.times_ms[0]), original.duration_ms, step_ms)
        grid_has_keyframes = {int(x) for x in original.times_ms} <= set(grid)
        inserted, dropped = _apply_grid(out, original, grid)
    removed: list[int] = []
    collinear = 0
    if max_error is not None:
        removed, collinear = _simplify(out.motion, original, max_error)
        for p in sorted(removed, reverse=True):
            out.delete_pose(p)
    tolerance = ROUNDING_RAD if max_error is None else max_error + ROUNDING_RAD
    deviation = compare_motions(original, out.motion, timestep_ms=1, tolerance=tolerance)
    return Resampled(
        document=out,
        step_ms=step_ms,
        grid_has_keyframes=grid_has_keyframes,
        inserted=inserted,
        dropped_off_grid=dropped,
        removed=len(removed),
        collinear=collinear,
        deviation=deviation,
    )
