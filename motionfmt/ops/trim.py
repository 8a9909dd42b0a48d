"""Trim a motion to a time window with exact boundary poses.

:func:`trim` keeps the poses inside a window as written, and at each boundary without a pose adds
one that holds the targets Webots' player commands there
(:func:`~motiontool.motionfmt.player.commands_at`; ``*`` where it sends none). The result is
never held: :meth:`Trimmed.blocks` gives its bytes a block of lines at a time, sliced from the
input's bytes, so that trimming holds the input and one block (it once held the input's lines,
the result's lines, its bytes and its read: eight times the file).
"""

from __future__ import annotations

import functools
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.retime import retimed_blocks
from motiontool.motionfmt.writer import TimeStyle, pose_lines, pose_name

if TYPE_CHECKING:
    from motiontool.motionfmt.motion import Motion

__all__ = ["Trimmed", "trim"]


@dataclass(frozen=True, eq=False)
class Trimmed:
    """What :func:`trim` did, and the result (:meth:`blocks`, :attr:`document`).

    Attributes:
        from_ms, to_ms: the window kept, ms, in the input's times (``to_ms`` clamped to the
            input's last pose).
        shift_ms: how much earlier every kept time is in the result, ms (0 with keep_times).
        kept: input poses kept (their lines keep their spelling, but for the time).
        inserted: boundary poses added (0, 1 or 2).
        source: the input document (not modified).
        first: the input's first kept pose (0-based; ``first + kept`` past the last).
        before, after: the boundary pose lines added before and after the kept ones
            (without their ends), ``b""`` where none.
    """

    from_ms: int
    to_ms: int
    shift_ms: int
    kept: int
    inserted: int
    source: MotionDocument
    first: int
    before: bytes
    after: bytes

    @property
    def n_poses(self) -> int:
        """The result's poses."""
        return self.kept + self.inserted

    @property
    def duration_ms(self) -> int:
        """The result's last pose time, ms: the window's end, in the result's times."""
        return self.to_ms - self.shift_ms

    def blocks(self) -> Iterator[bytes]:
        """The result's bytes, a block of lines at a time (:func:`retimed_blocks`): the
        input's header, the boundary poses and the kept pose lines (the times re-spelt where
        shifted), then what follows the input's last pose."""
        poses = range(self.first, self.first + self.kept)
        times = self.source.motion.times_ms[poses.start : poses.stop] - self.shift_ms
        return retimed_blocks(self.source, poses, times.tolist(), self.before, self.after)

    @functools.cached_property
    def document(self) -> MotionDocument:
        """The result, read as a document (joined from :meth:`blocks` on first use)."""
        return loads(b"".join(self.blocks()), self.source.path)


def _boundary_line(motion: Motion, at_ms: int, time_ms: int, style: TimeStyle) -> bytes:
    """The pose line (without its end) at ``time_ms`` holding what Webots commands at ``at_ms``
    (both ms)."""
    import numpy as np

    from motiontool.motionfmt.player import commands_at

    targets, sent = commands_at(motion, np.asarray([at_ms], dtype=np.int64))
    row = np.where(sent[0], targets[0], np.nan)[None, :]
    return pose_lines([time_ms], [pose_name(time_ms)], row, style)[0].encode("utf-8")


def _window(from_ms: int | None, to_ms: int | None, last: int) -> tuple[int, int]:
    """(from, to) of the window kept, ms: the whole motion by default, ``to`` clamped to the
    ``last`` pose time; raises :class:`MotionToolError` where nothing is left to keep."""
    lo = 0 if from_ms is None else int(from_ms)
    hi = last if to_ms is None else min(int(to_ms), last)
    if lo < 0 or (to_ms is not None and to_ms < 0):
        raise MotionToolError("trim times cannot be negative")
    if lo >= hi:
        raise MotionToolError(
            f"nothing to keep between {lo} ms and {hi} ms (the motion ends at {last} ms): "
            "the window must start before it ends and before the last pose"
        )
    return lo, hi


def trim(
    doc: MotionDocument,
    from_ms: int | None = None,
    to_ms: int | None = None,
    *,
    keep_times: bool = False,
) -> Trimmed:
    """Keep the part of ``doc`` between ``from_ms`` and ``to_ms`` (playback times, ms).

    The poses strictly inside are kept as written; at each boundary without a pose, a new pose
    holds exactly what Webots' player commands there (its interpolation, bit for bit; ``*``
    where a segment touching ``*`` sends no command). Times are shifted so the result starts
    at 0, unless ``keep_times`` (then the first pose is at ``from_ms``: MT206). ``to_ms`` past
    the last pose is clamped to it; ``from_ms`` before the first pose starts with the first
    pose's targets, which Webots commands from t = 0. A boundary that is a pose of the file
    keeps its line as written: where the segment into it touches ``*``, Webots sends that joint
    nothing at that one instant in the original, and the trimmed file commands it there.

    Raises:
        MotionToolError: ``from_ms >= to_ms``, a negative time, ``from_ms`` at or past the end,
            or a ``nan``/``inf`` command.
    """
    motion = doc.motion
    refuse_non_finite(motion, doc.result, "trimming")
    times = motion.times_ms
    lo, hi = _window(from_ms, to_ms, int(times[-1]))
    shift = 0 if keep_times else lo
    first, stop = (int(i) for i in times.searchsorted([lo, hi], side="left"))
    if stop < len(times) and int(times[stop]) == hi:
        stop += 1  # the inside poses: lo <= t <= hi
    before = after = b""
    if first == stop or int(times[first]) != lo:
        before = _boundary_line(motion, lo, lo - shift, doc.time_style)
    if first == stop or int(times[stop - 1]) != hi:
        after = _boundary_line(motion, hi, hi - shift, doc.time_style)
    inserted = (before != b"") + (after != b"")
    return Trimmed(lo, hi, shift, stop - first, inserted, doc, first, before, after)
