"""Trim a motion to a time window with exact boundary poses.

:func:`trim` keeps the poses inside a window as written, and at each boundary without a pose adds
one that holds the targets Webots' player commands there
(:func:`~motiontool.motionfmt.player.commands_at`; ``*`` where it sends none).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.ops._cells import PoseLines, set_time, with_eol
from motiontool.motionfmt.writer import TimeStyle, format_time, pose_lines, pose_name

if TYPE_CHECKING:
    from motiontool.motionfmt.motion import Motion

__all__ = ["Trimmed", "trim"]


@dataclass(frozen=True)
class Trimmed:
    """What :func:`trim` did.

    Attributes:
        document: the trimmed document.
        from_ms, to_ms: the window kept, ms, in the input's times (``to_ms`` clamped to the
            input's last pose).
        shift_ms: how much earlier every kept time is in the result, ms (0 with keep_times).
        kept: input poses kept (their lines keep their spelling, but for the time).
        inserted: boundary poses added (0, 1 or 2).
    """

    document: MotionDocument
    from_ms: int
    to_ms: int
    shift_ms: int
    kept: int
    inserted: int


def _boundary_line(motion: Motion, at_ms: int, time_ms: int, style: TimeStyle, eol: bytes) -> bytes:
    import numpy as np

    from motiontool.motionfmt.player import commands_at

    targets, sent = commands_at(motion, np.asarray([at_ms], dtype=np.int64))
    row = np.where(sent[0], targets[0], np.nan)[None, :]
    return pose_lines([time_ms], [pose_name(time_ms)], row, style)[0].encode("utf-8") + eol


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
    import numpy as np

    motion = doc.motion
    refuse_non_finite(motion, doc.result, "trimming")
    times = motion.times_ms
    lo, hi = _window(from_ms, to_ms, int(times[-1]))
    shift = 0 if keep_times else lo
    lines = PoseLines.of(doc)
    style = doc.time_style
    eol = lines.eol
    inside = np.flatnonzero((times >= lo) & (times <= hi)).tolist()
    poses: list[bytes] = []
    inserted = 0
    if not inside or int(times[inside[0]]) != lo:
        poses.append(_boundary_line(motion, lo, lo - shift, style, eol))
        inserted += 1
    for p in inside:
        t = int(times[p]) - shift
        line = lines.poses[p]
        if shift:
            line = set_time(line, format_time(t, style).encode("ascii"))
        poses.append(with_eol(line, eol))
    if not inside or int(times[inside[-1]]) != hi:
        poses.append(_boundary_line(motion, hi, hi - shift, style, eol))
        inserted += 1
    if not lines.final_newline and not lines.suffix:
        poses[-1] = with_eol(poses[-1], b"")
    out = PoseLines(lines.header, poses, lines.suffix, eol, lines.final_newline)
    document = loads(out.to_bytes(), doc.path)
    return Trimmed(document, lo, hi, shift, len(inside), inserted)
