"""Retime a motion: new pose times, never new values, in whole milliseconds, always strictly
increasing, all of it here.

* :func:`scale_times` plays it faster or slower, :func:`fit_duration` makes it last a given time,
  and :func:`fit_limits` stretches every segment that is too fast for a joint (its maximum
  velocity, and optionally an acceleration limit) to the shortest whole-ms duration that is not;
  all three answer a :class:`Retimed`.
* :func:`retimed_blocks` writes a document's pose lines with new times, a block of lines at a
  time: what ``trim`` (a window of poses, shifted, between boundary poses) and ``retime
  --speed`` / ``--duration`` (every pose) write, so that neither holds its result (the lines
  are sliced from the input's bytes and only the time cells that change are re-spelt).

Pure numpy: no robot knowledge. Velocity limits come in as ``{joint name: max velocity}``.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, overload

from motiontool.errors import MotionToolError
from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.ops import _cells
from motiontool.motionfmt.ops._cells import (
    header_eol,
    pose_block,
    pose_line_blocks,
    set_time,
    with_eol,
)
from motiontool.motionfmt.units import MS_PER_S
from motiontool.motionfmt.writer import format_time

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.document import MotionDocument

__all__ = [
    "DEFAULT_MARGIN",
    "MAX_TIME_MS",
    "Retimed",
    "Stretch",
    "TimeOverflowError",
    "fit_duration",
    "fit_limits",
    "require_in_range",
    "retimed_blocks",
    "scale_times",
]

MAX_TIME_MS = INT_MAX
"""The longest pose time a ``.motion`` file can hold, 2³¹−1 ms: Webots keeps times in a C
``int``, and ``validate`` rejects a later one (MT112)."""


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
        stretches: the segments :func:`fit_limits` lengthened (empty for the
            other retimings).
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


DEFAULT_MARGIN = 0.9
"""Fraction of a joint's maximum velocity that :func:`fit_limits` allows by default."""

_ACCEL_ROUNDS = 400  # rounds of _fit_acceleration; the second half slows down uniformly


@overload
def _velocity_ok(delta: float, duration_ms: int, vmax: float) -> bool: ...
@overload
def _velocity_ok(
    delta: npt.NDArray[np.float64],
    duration_ms: npt.NDArray[np.int64],
    vmax: npt.NDArray[np.float64],
) -> npt.NDArray[np.bool_]: ...
def _velocity_ok(delta: Any, duration_ms: Any, vmax: Any) -> Any:
    """|delta| moved in ``duration_ms`` stays within ``vmax`` (units per second); element by
    element for arrays (the one home of the rule the fit decides by)."""
    return delta / (duration_ms / MS_PER_S) <= vmax


def fit_limits(
    times_ms: Sequence[int],
    joints: Sequence[str],
    values: npt.ArrayLike,
    max_velocity: Mapping[str, float],
    *,
    margin: float = DEFAULT_MARGIN,
    max_acceleration: float | None = None,
    step_ms: int | None = None,
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
        step_ms: the controller's time step, ms: a segment whose duration is a whole number of
            steps is stretched to a whole number of them (the shortest that is within the
            limits), so that pose times on the step stay on it (Webots plays a pose time off
            the step at the step after it: MT209). None: whole ms.

    Returns:
        a :class:`Retimed`: a segment already within the limits keeps its duration; the first
        pose keeps its time; durations are whole ms (whole steps, see ``step_ms``), rounded up
        so that no limit is exceeded. Applying it again changes nothing.

    Raises:
        TimeOverflowError: the stretched motion would end past :data:`MAX_TIME_MS`.
    """
    import numpy as np

    _refuse_options(margin, max_acceleration, step_ms)
    old = [int(t) for t in times_ms]
    v = np.asarray(values, dtype=np.float64).reshape(len(old), len(joints))
    limits = np.array([max_velocity.get(name, math.inf) for name in joints], dtype=np.float64)
    unconstrained = tuple(
        dict.fromkeys(n for n, lim in zip(joints, limits, strict=True) if not math.isfinite(lim))
    )
    if len(old) < 2:
        return Retimed(tuple(old), tuple(old), (), unconstrained)
    cols = np.flatnonzero(np.isfinite(limits))
    reason: dict[int, tuple[str, str]] = {}
    dur = _fit_velocity(
        old, v[:, cols], limits[cols] * margin, [joints[int(c)] for c in cols], reason
    )
    on_step = _on_step(old, step_ms)
    dur = on_step(dur)
    if max_acceleration is not None:
        dur = _fit_acceleration(dur, v[:, cols], max_acceleration, joints, cols, reason, on_step)
    return _retimed(old, dur, reason, unconstrained)


def _refuse_options(margin: float, max_acceleration: float | None, step_ms: int | None) -> None:
    """Raise :class:`MotionToolError` for an option of :func:`fit_limits` out of its range."""
    if not (0 < margin <= 1):
        raise MotionToolError(f"the margin must be in (0, 1], got {margin}")
    if max_acceleration is not None and not (max_acceleration > 0):
        raise MotionToolError(f"the acceleration limit must be > 0 rad/s², got {max_acceleration}")
    if step_ms is not None and not step_ms >= 1:
        raise MotionToolError(f"the time step must be a whole number of ms >= 1, got {step_ms}")


def _on_step(old: list[int], step_ms: int | None) -> Callable[[list[int]], list[int]]:
    """What keeps pose times on the controller's step: of new segment durations (ms), each
    stretched one whose old duration in ``old`` (pose times, ms) is a whole number of
    ``step_ms`` rounded up to a whole number of it (None: the durations as they are)."""
    if step_ms is None:
        return lambda dur: dur
    old_dur = [b - a for a, b in itertools.pairwise(old)]

    def round_up(dur: list[int]) -> list[int]:
        return [
            -(-d // step_ms) * step_ms if d > o and o % step_ms == 0 else d
            for d, o in zip(dur, old_dur, strict=True)
        ]

    return round_up


def _retimed(
    old: list[int],
    dur: list[int],
    reason: dict[int, tuple[str, str]],
    unconstrained: tuple[str, ...],
) -> Retimed:
    """The pose times from the first one and the new segment durations ``dur`` (ms), and the
    segments that changed, each with its ``reason``."""
    import numpy as np

    new = [old[0]]
    for d in dur:
        new.append(new[-1] + int(d))
    require_in_range(new, "fitting the velocity limits")
    old_dur = np.diff(np.asarray(old)).tolist()
    stretches = tuple(
        Stretch(s, int(old_dur[s]), int(dur[s]), *reason[s])
        for s in range(len(dur))
        if dur[s] != old_dur[s]
    )
    return Retimed(tuple(old), tuple(new), stretches, unconstrained)


_FAR_MS = 1 << 53
"""A duration past every time a motion can hold (the fit then fails with
:class:`TimeOverflowError`): what a move too long for any whole
number of ms needs (1e306 rad)."""

_SEGMENTS = 1 << 14
"""Segments whose shortest durations are worked out at a time (as numpy arrays)."""


def _fit_velocity(
    old: list[int],
    v: npt.NDArray[np.float64],
    vlim: npt.NDArray[np.float64],
    names: list[str],
    reason: dict[int, tuple[str, str]],
    *,
    vectorised: bool = True,
) -> list[int]:
    """Segment durations (ms) after stretching each to the shortest whole ms in which every
    constrained column ``v`` (P, C) stays within its velocity ``vlim`` (C,); the joint that
    needed the most (the first of equals) goes into ``reason``.

    ``vectorised``: the durations of :data:`_SEGMENTS` segments at a time in numpy; False (or
    a limit that is not positive) takes the segment-by-segment loop below: the reference the
    numpy path is tested against (the same durations)."""
    import numpy as np

    with np.errstate(invalid="ignore", over="ignore"):
        delta = np.abs(np.diff(v, axis=0))  # (P-1, C), NaN where a '*' end
    # A '*' end, an 'inf' and a move too large for a double (1e308 to -1e308: no time fits
    # it) stretch nothing; the velocity check that checks the result reports them.
    delta = np.where(np.isfinite(delta), delta, 0.0)
    dur: list[int] = np.diff(np.asarray(old, dtype=np.int64)).tolist()
    if not names:
        return dur  # no column with a limit: nothing to fit
    if vectorised and bool((vlim > 0).all()):
        for lo in range(0, len(dur), _SEGMENTS):
            shortest = _shortest_ms_each(delta[lo : lo + _SEGMENTS], vlim)
            most, by = shortest.max(axis=1), shortest.argmax(axis=1)  # the first of equals
            for s in np.flatnonzero(most > np.asarray(dur[lo : lo + _SEGMENTS])).tolist():
                dur[lo + s] = int(most[s])
                reason[lo + s] = (names[int(by[s])], "velocity")
        return dur
    for s in range(len(dur)):
        need = dur[s]
        joint = ""
        for c in range(len(names)):
            d_c = float(delta[s, c])
            if d_c == 0.0:
                continue
            k = _shortest_ms(d_c, float(vlim[c]))
            if k > need:
                need, joint = k, names[c]
        if need > dur[s]:
            dur[s] = need
            reason[s] = (joint, "velocity")
    return dur


def _shortest_ms_each(
    delta: npt.NDArray[np.float64], vlim: npt.NDArray[np.float64]
) -> npt.NDArray[np.int64]:
    """:func:`_shortest_ms` of each move ``delta`` (S, C) with its column's limit ``vlim`` (C,),
    > 0; 0 where the move is 0 (it needs no time)."""
    import numpy as np

    with np.errstate(over="ignore"):  # a move of 1e306 rad: past every time (_FAR_MS)
        guess = np.ceil(delta / vlim * MS_PER_S)  # a first guess: ok() decides
    k = np.clip(guess, 1, _FAR_MS).astype(np.int64)

    def ok(duration: npt.NDArray[np.int64]) -> npt.NDArray[np.bool_]:
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # k - 1 = 0: masked
            return _velocity_ok(delta, duration, vlim) | (duration >= _FAR_MS)

    while not (low := ok(k)).all():
        k += ~low
    while (shorter := (k > 1) & ok(k - 1)).any():
        k -= shorter
    return np.where(delta == 0.0, 0, k)


def _shortest_ms(delta: float, vmax: float) -> int:
    """The fewest whole ms (at least 1) in which moving ``delta`` stays within ``vmax`` (units
    per second), exactly as :func:`_velocity_ok` decides it."""
    guess = delta / vmax * MS_PER_S  # a first guess: _velocity_ok decides
    if not guess < _FAR_MS:
        return _FAR_MS
    k = max(1, math.ceil(guess))
    while not _velocity_ok(delta, k, vmax):
        k += 1
    while k > 1 and _velocity_ok(delta, k - 1, vmax):
        k -= 1
    return k


def _accel_ratio(
    dur: npt.NDArray[np.float64], dq: npt.NDArray[np.float64], amax: float
) -> npt.NDArray[np.float64]:
    """(P, C) ratio |Δw| / allowed at each pose (boundaries: from and to rest); <= 1 is fine.

    ``dq`` is (P-1, C) signed segment displacements, NaN where a segment touches ``*``.
    """
    import numpy as np

    w = dq * MS_PER_S / dur[:, None]  # (S, C) segment velocities, unit/s
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
    on_step: Callable[[list[int]], list[int]],
) -> list[int]:
    """Lengthen segments (whole ms, never shorten; ``on_step`` rounds them, :func:`_on_step`)
    until every pose's velocity change is within ``amax``: a violated pose stretches both its
    segments by sqrt(ratio), which brings its own ratio to 1 (velocities scale by 1/f, the
    allowed change by f); neighbours are re-checked. If that does not settle, the whole motion
    is slowed uniformly, which always does."""
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
        dur = np.asarray(on_step([int(d) for d in np.ceil(dur * factor)]), dtype=np.float64)
    else:  # pragma: no cover - the uniform slow-down converges geometrically
        raise MotionToolError("could not fit the acceleration limit")
    fallback = joints[int(cols[0])] if cols.shape[0] else ""
    for s in np.flatnonzero(dur > start).tolist():
        reason[s] = (blame.get(s, fallback), "acceleration")
    return [int(d) for d in dur]


def retimed_blocks(
    doc: MotionDocument,
    poses: range,
    times_ms: Sequence[int],
    before: bytes = b"",
    after: bytes = b"",
    *,
    ends_as_header: bool = True,
) -> Iterator[bytes]:
    """The bytes of ``doc`` with only the pose lines ``poses`` (consecutive), pose
    ``poses[k]`` at ``times_ms[k]`` (ms: its time cell re-spelt in ``doc``'s time style where
    the time changes), after the pose line ``before`` and followed by ``after`` (lines without
    their ends; ``b""``: none), a block of :data:`~motiontool.motionfmt.ops._cells.BLOCK_LINES`
    lines at a time, never all held.

    The header, and what follows the last pose (lines after a terminating blank line, the
    final newline or its absence, which the last line then has too), stay as they are; every
    pose line ends as the header does (``ends_as_header``; False: as it did)."""
    data = doc.to_bytes()
    start, stop = pose_block(data, doc.n_poses)
    header = data[: start - 1]
    tail = data[stop:]
    eol = header_eol(header)
    last_eol = eol if tail else b""  # the end of the result's last line
    yield header
    if before:  # never the last line: a kept pose or ``after`` follows
        yield b"\n" + before + eol
    old = doc.result.times_ms
    style = doc.time_style
    size = _cells.BLOCK_LINES
    blocks = pose_line_blocks(data, (start, stop), size, poses.start, poses.stop)
    for a, lines in blocks:
        b = a + len(lines)
        for k, (was, now) in enumerate(
            zip(old[a:b].tolist(), times_ms[a - poses.start : b - poses.start], strict=True)
        ):
            if was != now:
                lines[k] = set_time(lines[k], format_time(int(now), style).encode("ascii"))
        if not ends_as_header:
            yield b"".join([b"\n" + line for line in lines])
            continue
        ends = [eol] * len(lines)
        if b == poses.stop and not after:
            ends[-1] = last_eol
        yield b"".join([b"\n" + with_eol(line, e) for line, e in zip(lines, ends, strict=True)])
    if after:
        yield b"\n" + after + last_eol
    yield tail
