"""Transforming motions without losing anything: resample onto a grid, drop keyframes, retime.

Everything edits a lossless :class:`~motiontool.motionfmt.document.MotionDocument`, so the lines
and cells a transform keeps keep their original spelling; new poses are spelt canonically.

* :func:`resample` puts keyframes on a uniform grid of pose times and, with ``max_error``, removes
  the keyframes that the command stream does not need. Where the grid holds every original pose
  time the result is *lossless*: a new keyframe lies on its segment, so Webots' player commands
  the same targets at every playback time, to the last bits of floating-point rounding in its
  own interpolation (see :data:`ROUNDING_RAD`). ``*`` is kept: a new keyframe inside a segment
  that touches a ``*`` cell gets ``*`` too, so that segment stays uncommanded.
* :func:`scale_times`, :func:`fit_duration` and :func:`fit_limits` change pose times only, never
  values, in whole milliseconds, always strictly increasing.

Pure numpy: no robot knowledge. Velocity limits come in as ``{joint name: max velocity}``.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING

from motiontool.motionfmt.compare import MotionDiff, compare_motions
from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.player import targets_at

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = [
    "DEFAULT_MARGIN",
    "MAX_TIME_MS",
    "ROUNDING_RAD",
    "Resampled",
    "Retimed",
    "Stretch",
    "TimeOverflowError",
    "fit_duration",
    "fit_limits",
    "grid_times",
    "resample",
    "scale_times",
]

ROUNDING_RAD = 1e-12
"""Floating-point slack (rad, m for linear joints) on "on the line" and "within the bound".

Webots evaluates ``v[a] + (e - t[a]) * (v[b] - v[a]) / (t[b] - t[a])`` in double precision; a
point on a segment, re-interpolated between other points of the same segment, comes out a few
units in the last place off (~1e-16 rad for joint angles of a few radians). 1e-12 rad is far
above that rounding and far below anything a motor can resolve, so ``max_error=0`` still removes
exactly collinear keyframes."""

DEFAULT_MARGIN = 0.9
"""Fraction of a joint's maximum velocity that :func:`fit_limits` allows by default."""

MAX_TIME_MS = INT_MAX
"""The longest pose time a ``.motion`` file can hold, 2³¹−1 ms: Webots keeps times in a C
``int``, and ``validate`` rejects a later one (MT112)."""

_ACCEL_ROUNDS = 400  # rounds of _fit_acceleration; the second half slows down uniformly


# --------------------------------------------------------------------------- resample


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
    values = targets_at(original, np.asarray(new, dtype=np.int64)).tolist()
    for t, row in zip(new, values, strict=True):
        index = bisect.bisect_left(times, t)
        doc.insert_pose(index, t, _pose_name(t), row)
        times.insert(index, t)
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


# --------------------------------------------------------------------------- retime


@dataclass(frozen=True)
class Stretch:
    """One segment :func:`fit_limits` made longer.

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
        stretches: the segments :func:`fit_limits` lengthened (empty for the other retimings).
        unconstrained: joints of the motion without a velocity limit (ignored by the fit).
        rounding_ms: the largest distance of a new pose time from the exact scaled time, ms
            (:func:`scale_times`, :func:`fit_duration`; 0 for :func:`fit_limits`).
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


def _in_range(new: Sequence[int], how: str) -> None:
    if new and new[-1] > MAX_TIME_MS:
        raise TimeOverflowError(int(new[-1]), how)


def _round_half_up(x: Fraction) -> int:
    return math.floor(x + Fraction(1, 2))


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
    exact = [Fraction(int(t)) / Fraction(speed) for t in times_ms]
    new = _strictly_increasing([_round_half_up(x) for x in exact])
    _in_range(new, f"retiming at speed x{speed:g}")
    return Retimed(tuple(int(t) for t in times_ms), tuple(new), rounding_ms=_off(new, exact))


def _off(new: Sequence[int], exact: Sequence[Fraction]) -> float:
    return float(max(abs(n - x) for n, x in zip(new, exact, strict=True)))


def fit_duration(times_ms: Sequence[int], duration_ms: int) -> Retimed:
    """Scale every pose time (from 0) so that the last pose is at ``duration_ms`` ms exactly.

    Raises:
        TimeOverflowError: ``duration_ms`` is past :data:`MAX_TIME_MS`.
    """
    old = [int(t) for t in times_ms]
    last = old[-1]
    _in_range([duration_ms], f"retiming to a duration of {duration_ms} ms")
    if duration_ms < len(old) - 1 or duration_ms < 0:
        raise MotionToolError(
            f"a duration of {duration_ms} ms cannot hold {len(old)} poses at distinct whole ms; "
            f"give at least {len(old) - 1} ms"
        )
    if last == 0:
        raise MotionToolError("the motion's only pose time is 0 ms: there is no duration to scale")
    exact = [Fraction(t * duration_ms, last) for t in old]
    new = _strictly_increasing([_round_half_up(x) for x in exact], last_ms=duration_ms)
    return Retimed(tuple(old), tuple(new), rounding_ms=_off(new, exact))


def _velocity_ok(delta: float, duration_ms: int, vmax: float) -> bool:
    """|delta| moved in ``duration_ms`` stays within ``vmax`` (units per second)."""
    return delta / (duration_ms / 1000.0) <= vmax


def fit_limits(
    times_ms: Sequence[int],
    joints: Sequence[str],
    values: npt.ArrayLike,
    max_velocity: Mapping[str, float],
    *,
    margin: float = DEFAULT_MARGIN,
    max_acceleration: float | None = None,
) -> Retimed:
    """Stretch every segment that is too fast for a joint, to the shortest duration that is not.

    Args:
        times_ms: P pose times, ms, strictly increasing.
        joints: J column names (a name may repeat; every column is held to its limit).
        values: (P, J) float64 joint targets, rad (m), NaN for ``*``.
        max_velocity: ``{joint: maximum velocity}``, rad/s (m/s); a column not in it, or with an
            infinite limit, is not constrained (and listed in ``unconstrained``).
        margin: the fraction of the maximum velocity allowed, in (0, 1].
        max_acceleration: optional limit (rad/s²) on the change of a joint's segment velocity
            at each pose, taken over the half segments on either side
            (``|w[k] - w[k-1]| <= A * (d[k-1] + d[k]) / 2``), the motion starting and ending at
            rest. Segments touching ``*`` are not constrained.

    Returns:
        a :class:`Retimed`: a segment already within the limits keeps its duration; the first
        pose keeps its time; durations are whole ms, rounded up so that no limit is exceeded.
        Applying it again changes nothing.

    Raises:
        TimeOverflowError: the stretched motion would end past :data:`MAX_TIME_MS`.
    """
    import numpy as np

    if not (0 < margin <= 1):
        raise MotionToolError(f"the margin must be in (0, 1], got {margin}")
    if max_acceleration is not None and not (max_acceleration > 0):
        raise MotionToolError(f"the acceleration limit must be > 0 rad/s², got {max_acceleration}")
    old = [int(t) for t in times_ms]
    v = np.asarray(values, dtype=np.float64).reshape(len(old), len(joints))
    limits = np.array([max_velocity.get(name, math.inf) for name in joints], dtype=np.float64)
    unconstrained = tuple(
        dict.fromkeys(n for n, lim in zip(joints, limits, strict=True) if not math.isfinite(lim))
    )
    if len(old) < 2:
        return Retimed(tuple(old), tuple(old), (), unconstrained)
    cols = np.flatnonzero(np.isfinite(limits))
    vlim = limits[cols] * margin
    with np.errstate(invalid="ignore"):
        delta = np.abs(np.diff(v[:, cols], axis=0))  # (P-1, C), NaN where a '*' end
    delta = np.where(np.isfinite(delta), delta, 0.0)
    dur = np.diff(np.asarray(old, dtype=np.int64)).tolist()
    reason: dict[int, tuple[str, str]] = {}
    for s in range(len(dur)):
        need = dur[s]
        joint = ""
        for c in range(cols.shape[0]):
            d_c = float(delta[s, c])
            if d_c == 0.0:
                continue
            k = max(1, math.ceil(d_c * 1000.0 / float(vlim[c])))
            while not _velocity_ok(d_c, k, float(vlim[c])):
                k += 1
            while k > 1 and _velocity_ok(d_c, k - 1, float(vlim[c])):
                k -= 1
            if k > need:
                need, joint = k, joints[int(cols[c])]
        if need > dur[s]:
            dur[s] = need
            reason[s] = (joint, "velocity")
    if max_acceleration is not None:
        dur = _fit_acceleration(dur, v[:, cols], max_acceleration, joints, cols, reason)
    new = [old[0]]
    for d in dur:
        new.append(new[-1] + int(d))
    _in_range(new, "fitting the velocity limits")
    old_dur = np.diff(np.asarray(old)).tolist()
    stretches = tuple(
        Stretch(s, int(old_dur[s]), int(dur[s]), *reason[s])
        for s in range(len(dur))
        if dur[s] != old_dur[s]
    )
    return Retimed(tuple(old), tuple(new), stretches, unconstrained)


def _accel_ratio(
    dur: npt.NDArray[np.float64], dq: npt.NDArray[np.float64], amax: float
) -> npt.NDArray[np.float64]:
    """(P, C) ratio |Δw| / allowed at each pose (boundaries: from and to rest); <= 1 is fine.

    ``dq`` is (P-1, C) signed segment displacements, NaN where a segment touches ``*``.
    """
    import numpy as np

    w = dq * 1000.0 / dur[:, None]  # (S, C) segment velocities, unit/s
    zeros = np.zeros((1, w.shape[1]))
    w_in = np.vstack([zeros, w])  # velocity before pose k (rest before the first)
    w_out = np.vstack([w, zeros])  # velocity after pose k (rest after the last)
    half = np.concatenate([[0.0], dur]) + np.concatenate([dur, [0.0]])  # ms, d[k-1] + d[k]
    allowed = amax * half / 2000.0  # unit/s
    with np.errstate(invalid="ignore"):
        ratio = np.abs(w_out - w_in) / allowed[:, None]
    return np.where(np.isnan(ratio), 0.0, ratio)


def _fit_acceleration(
    dur_ms: list[int],
    v: npt.NDArray[np.float64],
    amax: float,
    joints: Sequence[str],
    cols: npt.NDArray[np.intp],
    reason: dict[int, tuple[str, str]],
) -> list[int]:
    """Lengthen segments (whole ms, never shorten) until every pose's velocity change is within
    ``amax``: a violated pose stretches both its segments by sqrt(ratio), which brings its own
    ratio to 1 (velocities scale by 1/f, the allowed change by f); neighbours are re-checked. If
    that does not settle, the whole motion is slowed uniformly, which always does."""
    import numpy as np

    with np.errstate(invalid="ignore"):
        dq = np.diff(v, axis=0)
    dur = np.asarray(dur_ms, dtype=np.float64)
    start = dur.copy()
    blame: dict[int, str] = {}
    for attempt in range(_ACCEL_ROUNDS):
        ratio = _accel_ratio(dur, dq, amax)
        worst = ratio.max(axis=1) if ratio.shape[1] else np.zeros(ratio.shape[0])
        bad = np.flatnonzero(worst > 1.0)
        if bad.shape[0] == 0:
            break
        factor = np.ones(dur.shape[0])
        for k in bad.tolist():
            f = math.sqrt(float(worst[k])) * (1.0 + 1e-6)
            joint = joints[int(cols[int(np.argmax(ratio[k]))])]
            for s in (k - 1, k):
                if 0 <= s < dur.shape[0]:
                    factor[s] = max(factor[s], f)
                    blame.setdefault(s, joint)
        if attempt >= _ACCEL_ROUNDS // 2:  # uniform slow-down: every ratio scales by 1/f**2
            factor[:] = factor.max()
        dur = np.ceil(dur * factor)
    else:  # pragma: no cover - the uniform slow-down converges geometrically
        raise MotionToolError("could not fit the acceleration limit")
    fallback = joints[int(cols[0])] if cols.shape[0] else ""
    for s in np.flatnonzero(dur > start).tolist():
        reason[s] = (blame.get(s, fallback), "acceleration")
    return [int(d) for d in dur]
