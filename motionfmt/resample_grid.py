"""``resample --step``: a motion's keyframes on a uniform grid of pose times, written and compared
a block at a time, so that memory stays flat however long the motion lasts (a 10-hour motion
at 20 ms is 1.8 million new poses; the result was once held whole, read back and compared,
3 GB for 22 joints).

The grid is every multiple of the step between the first and the last pose time, and both ends.
An original pose on the grid keeps its line; one off the grid is left out; each grid time
without a pose gets a new, canonically spelt pose with the target Webots commands there
(:func:`~motiontool.motionfmt.player.targets_at`: ``*`` inside a segment touching ``*``). The
result is never held: :meth:`GridResample.blocks` gives its bytes a block at a time
(:meth:`~motiontool.motionfmt.document.MotionDocument.stream_edited`), and
:meth:`GridResample.commands_at` what Webots plays from it at any playback times, from the grid
poses around them only, so that :func:`~motiontool.motionfmt.compare.compare_motions` compares it
with the original a window at a time (bit for bit what the written file, read back, commands).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.compare_steps import MARKER_MARGIN
from motiontool.motionfmt.document import MotionDocument
from motiontool.motionfmt.motion import Motion
from motiontool.motionfmt.player import commands_at, targets_at
from motiontool.motionfmt.reader import NO_VALUE_MARKER
from motiontool.motionfmt.writer import pose_lines, pose_name

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["Grid", "GridResample"]

_BLOCK = 8192
"""Grid times handled at once (new lines spelt, targets computed)."""


@dataclass(frozen=True)
class Grid:
    """The multiples of ``step_ms`` between ``first_ms`` and ``last_ms``, and both ends (ms)."""

    first_ms: int
    last_ms: int
    step_ms: int

    def __post_init__(self) -> None:
        if self.step_ms <= 0:
            raise MotionToolError(
                f"the grid step must be a positive number of ms, got {self.step_ms}"
            )

    def between(self, lo: int, hi: int) -> npt.NDArray[np.int64]:
        """The grid times in ``[lo, hi]``, ascending (int64)."""
        import numpy as np

        lo, hi = max(lo, self.first_ms), min(hi, self.last_ms)
        if lo > hi:
            return np.empty(0, dtype=np.int64)
        step = self.step_ms
        times = np.arange(-(-lo // step), hi // step + 1, dtype=np.int64) * step
        if lo == self.first_ms and lo % step:
            times = np.concatenate(([lo], times))
        if hi == self.last_ms and hi % step and hi != self.first_ms:
            times = np.concatenate((times, [hi]))
        return times

    def count(self) -> int:
        """How many grid times there are."""
        step = self.step_ms
        multiples = max(0, self.last_ms // step - -(-self.first_ms // step) + 1)
        ends = (self.first_ms % step != 0) + (
            self.last_ms % step != 0 and self.last_ms != self.first_ms
        )
        return multiples + ends

    def before(self, ms: int) -> int:
        """The last grid time before ``ms`` (the first one if there is none)."""
        if ms > self.last_ms:
            return self.last_ms
        if ms <= self.first_ms:
            return self.first_ms
        return max((-(-ms // self.step_ms) - 1) * self.step_ms, self.first_ms)

    def after(self, ms: int) -> int:
        """The first grid time after ``ms`` (the last one if there is none)."""
        if ms < self.first_ms:
            return self.first_ms
        if ms >= self.last_ms:
            return self.last_ms
        return min((ms // self.step_ms + 1) * self.step_ms, self.last_ms)

    def holds(self, times_ms: npt.NDArray[np.int64]) -> npt.NDArray[np.bool_]:
        """Which of ``times_ms`` (within the grid's span) are grid times."""
        on: npt.NDArray[np.bool_] = times_ms % self.step_ms == 0
        on |= times_ms == self.first_ms
        on |= times_ms == self.last_ms
        return on


class GridResample:
    """``doc`` (whose motion is ``original``) with its keyframes on the grid of ``step_ms``.

    Attributes:
        grid: the grid.
        kept: per original pose, whether it lies on the grid (its line stays).
        inserted: new poses (grid times without an original pose).
        dropped: original poses off the grid.
        n_poses, duration_ms, joints: the result's pose count, last pose time (ms), joints.
    """

    def __init__(self, doc: MotionDocument, original: Motion, step_ms: int) -> None:
        times = original.times_ms
        self.doc, self.original = doc, original
        self.grid = Grid(int(times[0]), int(times[-1]), step_ms)
        self.kept = self.grid.holds(times)
        kept = int(self.kept.sum())
        self.n_poses = self.grid.count()
        self.inserted = self.n_poses - kept
        self.dropped = len(times) - kept
        self.duration_ms = self.grid.last_ms
        self.joints = original.joints

    def blocks(self) -> Iterator[bytes]:
        """The result's bytes, a block at a time."""
        return self.doc.stream_edited(self.kept.tolist(), _NewLines(self).after)

    def _blocks(self, lo: int, hi: int) -> Iterator[npt.NDArray[np.int64]]:
        """The grid times in ``[lo, hi]``, at most :data:`_BLOCK` at a time."""
        step = self.grid.step_ms
        while lo <= hi:
            block = self.grid.between(lo, min(hi, lo + _BLOCK * step - 1))  # _BLOCK multiples
            if block.shape[0] == 0:
                return
            yield block
            lo = int(block[-1]) + 1

    def marker_free(self) -> bool:
        """Whether no value of the original, hence of the result, comes near Webots' no-value
        marker: where one does, :func:`~motiontool.motionfmt.compare.compare_motions` needs every
        step of the segments near it (and the result whole)."""
        import numpy as np

        values = self.original.values
        with np.errstate(invalid="ignore"):
            return not bool((values <= NO_VALUE_MARKER + MARKER_MARGIN).any())

    def time_blocks(self) -> Iterator[npt.NDArray[np.int64]]:
        """The result's pose times, ascending, a block at a time."""
        return self._blocks(self.grid.first_ms, self.grid.last_ms)

    def commands_at(
        self, elapsed_ms: npt.NDArray[np.int64]
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """What Webots sends, playing the result, at the playback times ``elapsed_ms`` (as
        :func:`~motiontool.motionfmt.player.commands_at` of the result read back), from the grid
        poses around them."""
        e = elapsed_ms
        window = self._window(self.grid.before(int(e.min())), self.grid.after(int(e.max())))
        return commands_at(window, e)

    def _window(self, lo: int, hi: int) -> Motion:
        """The result's poses from ``lo`` to ``hi`` (grid times, ms) as a :class:`Motion`: a
        new pose's target, an original pose's own row."""
        import numpy as np

        times = self.grid.between(lo, hi)
        values = targets_at(self.original, times)
        commanded = ~np.isnan(values)
        t0 = self.original.times_ms
        at = np.minimum(np.searchsorted(t0, times), t0.shape[0] - 1)
        own = t0[at] == times
        values[own] = self.original.values[at[own]]
        commanded[own] = self.original.commanded[at[own]]
        return Motion(self.joints, ("",) * times.shape[0], times, values, commanded)


class _NewLines:
    """The new pose lines of a :class:`GridResample`, spelt :data:`_BLOCK` grid times at a time
    whatever segments of the original they fall in (a file of short segments has a new line or
    none in each: spelt a segment at a time, a line cost a call of its own), and handed out
    segment by segment as :meth:`~motiontool.motionfmt.document.MotionDocument.stream_edited`
    asks for them, in order."""

    def __init__(self, gridded: GridResample) -> None:
        self._gridded = gridded
        self._times = gridded.time_blocks()
        self._lines: list[str] = []
        self._runs: list[tuple[int, int]] = []  # (original pose before, end): lines by segment
        self._run = 0  # the first run not handed out
        self._at = 0  # its first line

    def after(self, pose: int) -> Iterator[list[str]]:
        """The new pose lines between original pose ``pose`` and the next, a block at a time
        (asked for every pose, in order: a segment's lines may end one block and start the next)."""
        while self._run < len(self._runs) or self._fill():
            segment, end = self._runs[self._run]
            if segment != pose:
                return
            yield self._lines[self._at : end]
            self._run, self._at = self._run + 1, end

    def _fill(self) -> bool:
        """Spell the new lines of the next block of grid times that has one; False at the end."""
        import numpy as np

        original = self._gridded.original
        t0 = original.times_ms
        for block in self._times:
            at = np.searchsorted(t0, block)  # the first original pose at or after each
            new = block[t0[np.minimum(at, t0.shape[0] - 1)] != block]
            if new.shape[0] == 0:
                continue
            values = targets_at(original, new)
            names = [pose_name(t) for t in new.tolist()]
            self._lines = pose_lines(new, names, values, self._gridded.doc.time_style)
            segment = np.searchsorted(t0, new) - 1
            ends = np.append(np.flatnonzero(segment[1:] != segment[:-1]) + 1, new.shape[0])
            self._runs = list(zip(segment[ends - 1].tolist(), ends.tolist(), strict=True))
            self._run = self._at = 0
            return True
        return False
