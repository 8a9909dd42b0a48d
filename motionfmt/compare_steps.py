"""Which steps of the comparison grid decide a comparison (:mod:`~motiontool.motionfmt.compare`):
every step of a grid up to :data:`~motiontool.motionfmt.compare.EVERY_STEP_LIMIT`, else the
steps next to each pose time of either motion (and every step of a segment that reaches Webots'
no-value marker), in chunks, each with how many grid steps it stands for; for a motion held
whole (:class:`~motiontool.motionfmt.motion.Motion`) or known a window at a time
(:class:`Played`)."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, Protocol

from motiontool.motionfmt.arrays import sorted_distinct
from motiontool.motionfmt.reader import NO_VALUE_MARKER

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["MARKER_MARGIN", "Played", "compared_steps", "every_step", "played_steps"]

MARKER_MARGIN = 1e-6 * abs(NO_VALUE_MARKER)
"""How near Webots' no-value marker a value counts as reaching it (a command it may skip), far
above floating-point rounding: where one does, a comparison needs every step near it."""

_CHUNK_STEPS = 1 << 14  # steps compared at once: bounds memory to a few MB per joint block


def every_step(n_steps: int) -> Iterator[tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]]:
    """Every step of the grid ``0 .. n_steps - 1``, in chunks, each standing for itself."""
    import numpy as np

    return _weighted(_merged(np.empty(0, dtype=np.int64), [(0, n_steps)], n_steps), n_steps)


def compared_steps(
    motions: Sequence[Motion], timestep_ms: int, n_steps: int
) -> Iterator[tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]]:
    """The steps of the grid ``0 .. n_steps - 1`` that decide the comparison, in chunks of at
    most :data:`_CHUNK_STEPS`, each with how many grid steps it stands for (itself and the
    steps up to the next one).

    Between two pose times of either motion, each command is a linear interpolation of the
    step (or a constant: before the first pose, after the last, or held where nothing is
    sent), so |Δq| is largest at a first or last step of such a run of steps, and which side
    holds a target is the same all along it. So the steps next to each pose time (two either
    side) are enough, whatever the motion's duration; but every step of a segment whose values
    reach Webots' no-value marker, where one step may skip its target."""
    import numpy as np

    points = [np.array([0, n_steps - 1], dtype=np.int64)]
    dense: list[tuple[int, int]] = []
    for m in motions:
        t = m.times_ms
        below, above = t // timestep_ms, -(-t // timestep_ms)
        points.append(_points(t, timestep_ms))
        for a in _marker_segments(m):
            dense.append((int(below[a]), int(above[a + 1]) + 1))
    steps = np.concatenate(points)
    steps = steps[(steps >= 0) & (steps < n_steps)]
    return _weighted(_merged(sorted_distinct(steps), dense, n_steps), n_steps)


def _marker_segments(motion: Motion) -> list[int]:
    """The segments (index of their first pose) where a column's interpolated value can equal
    :data:`~motiontool.motionfmt.reader.NO_VALUE_MARKER` (Webots then sends nothing), within a
    margin far above rounding."""
    import numpy as np

    v = motion.values
    if v.shape[0] < 2:
        return []
    lo, hi = np.fmin(v[:-1], v[1:]), np.fmax(v[:-1], v[1:])
    with np.errstate(invalid="ignore"):
        near = (lo <= NO_VALUE_MARKER + MARKER_MARGIN) & (hi >= NO_VALUE_MARKER - MARKER_MARGIN)
    return np.flatnonzero(near.any(axis=1)).tolist()


def _merged(
    sparse: npt.NDArray[np.int64], dense: list[tuple[int, int]], n_steps: int
) -> Iterator[npt.NDArray[np.int64]]:
    """``sparse`` steps and every step of the ``dense`` ranges ``[start, end)``, sorted, each
    once, in arrays of at most :data:`_CHUNK_STEPS`."""
    import numpy as np

    done = 0  # every step below it is given
    for start, end in sorted(dense):
        start, end = max(start, done), min(end, n_steps)
        if start >= end:
            continue
        yield from _chunks(sparse[(sparse >= done) & (sparse < start)])
        for first in range(start, end, _CHUNK_STEPS):
            yield np.arange(first, min(first + _CHUNK_STEPS, end), dtype=np.int64)
        done = end
    yield from _chunks(sparse[sparse >= done])


def _chunks(steps: npt.NDArray[np.int64]) -> Iterator[npt.NDArray[np.int64]]:
    for first in range(0, steps.shape[0], _CHUNK_STEPS):
        yield steps[first : first + _CHUNK_STEPS]


def _weighted(
    chunks: Iterator[npt.NDArray[np.int64]], n_steps: int
) -> Iterator[tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]]:
    """Each chunk of sorted steps with how many grid steps each stands for: up to the next
    step of the next chunks, the last one up to ``n_steps``."""
    import numpy as np

    pending = None
    for steps in chunks:
        if not steps.shape[0]:
            continue
        if pending is not None:
            yield pending, np.diff(np.append(pending, steps[0]))
        pending = steps
    if pending is not None:
        yield pending, np.diff(np.append(pending, n_steps))


class Played(Protocol):
    """A motion too long to hold, known a window at a time
    (:class:`~motiontool.motionfmt.resample_grid.GridResample`): what
    :func:`compare_motions` needs of it."""

    @property
    def joints(self) -> tuple[str, ...]: ...
    @property
    def duration_ms(self) -> int: ...
    @property
    def n_poses(self) -> int: ...

    def commands_at(
        self, elapsed_ms: npt.NDArray[np.int64]
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """As :func:`~motiontool.motionfmt.player.commands_at` of the whole motion."""
        ...

    def time_blocks(self) -> Iterator[npt.NDArray[np.int64]]:
        """The pose times, ascending, a block at a time."""
        ...

    def marker_free(self) -> bool:
        """Whether no value comes near Webots' no-value marker (see :func:`_marker_segments`)."""
        ...


def _points(times_ms: npt.NDArray[np.int64], timestep_ms: int) -> npt.NDArray[np.int64]:
    """The steps next to each pose time (two either side): see :func:`compared_steps`."""
    import numpy as np

    below, above = times_ms // timestep_ms, -(-times_ms // timestep_ms)
    return np.concatenate([below - 1, below, above, above + 1])


def played_steps(
    old: Motion, new: Played, timestep_ms: int, n_steps: int
) -> Iterator[tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]]:
    """:func:`compared_steps` of ``old`` and a motion known a block of pose times at a time:
    the same steps with the same weights, found a window of ``new``'s times at a time (neither
    motion reaches the no-value marker: no segment is compared at every step)."""
    import numpy as np

    if not new.marker_free() or _marker_segments(old):
        raise ValueError("a played motion is compared only where no value nears the marker")
    ends = np.array([0, n_steps - 1], dtype=np.int64)
    fixed = sorted_distinct(np.concatenate([ends, _points(old.times_ms, timestep_ms)]))
    fixed = fixed[(fixed >= 0) & (fixed < n_steps)]

    def windows() -> Iterator[npt.NDArray[np.int64]]:
        # A window ends at the first step of the next block's first time t. A point of this
        # block at or past it lies between t // T - 1 and ceil(t / T) + 1, all steps of t's
        # own four points: it is the next window's, and left to it.
        start = 0
        blocks = new.time_blocks()
        block = next(blocks, None)
        while block is not None:
            following = next(blocks, None)
            end = n_steps if following is None else int(following[0]) // timestep_ms - 1
            points = _points(block, timestep_ms)
            here = points < end
            lo, hi = np.searchsorted(fixed, [start, end])
            steps = sorted_distinct(np.concatenate([fixed[lo:hi], points[here]]))
            yield from _chunks(steps[(steps >= 0) & (steps < n_steps)])
            start, block = end, following

    return _weighted(windows(), n_steps)
