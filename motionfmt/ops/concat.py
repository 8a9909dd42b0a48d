"""Concatenate motions: play them one after another, joined by transitions.

:func:`concat` joins motions with a transition from one's last pose to the next one's first pose
that is the shortest duration within maxVelocity x margin, in whole controller steps
(:func:`~motiontool.motionfmt.retime.fit_limits`, the logic of ``retime --fit-limits``), or a
given one. The inputs' pose lines keep their spelling, but for their times.
"""

from __future__ import annotations

import io
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.document import MotionDocument
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.ops._cells import (
    PoseLines,
    ReadOnUse,
    cell_columns,
    cell_tokens,
    join_columns,
    refuse_duplicates,
    set_time,
    with_eol,
    write_lines,
)
from motiontool.motionfmt.retime import DEFAULT_MARGIN, MAX_TIME_MS, fit_limits
from motiontool.motionfmt.writer import TimeStyle, format_time

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["Concatenated", "Transition", "concat"]


@dataclass(frozen=True)
class Transition:
    """One transition :func:`concat` inserted.

    Attributes:
        into: the path of the motion the transition leads into.
        start_ms: when it starts (the previous motion's last pose), ms, in the result.
        duration_ms: how long it lasts, ms.
        joint: the joint that needed the most time ('' when none moves or it was given).
        fitted: True when the duration was fitted to the velocity limits, False when given.
    """

    into: str
    start_ms: int
    duration_ms: int
    joint: str
    fitted: bool


@dataclass(frozen=True, eq=False)
class Concatenated(ReadOnUse):
    """What :func:`concat` did.

    Attributes:
        data: the joined file's bytes (the first input's header and lines first).
        path: its name (the first input's).
        transitions: one per joint between two inputs.
        reordered: inputs whose columns were put in the first input's order.
        dropped_lines: lines after a terminating blank line (ignored by Webots) left out.
        unconstrained: joints without a velocity limit (not constrained by the fit).
    """

    data: bytes
    path: str
    transitions: tuple[Transition, ...]
    reordered: tuple[str, ...]
    dropped_lines: int
    unconstrained: tuple[str, ...]


def concat(
    docs: Sequence[MotionDocument],
    *,
    transition_ms: int | None = None,
    max_velocity: Mapping[str, float] | None = None,
    margin: float = DEFAULT_MARGIN,
    step_ms: int | None = None,
) -> Concatenated:
    """Join ``docs`` one after another.

    Args:
        docs: two or more documents with the same joints (each once; any column order: the
            later ones are put in the first one's order, cell by cell, keeping spellings).
        transition_ms: the time from one motion's last pose to the next one's first pose, ms
            (>= 1). When None it is fitted: the shortest whole-ms duration in which every
            joint that both poses command moves within ``margin`` x its maximum velocity
            (``max_velocity``, rad/s or m/s), at least 1 ms.
        max_velocity: ``{joint: max velocity}``, rad/s (m/s); needed when ``transition_ms`` is
            None. A joint not in it is not constrained.
        margin: the fraction of the maximum velocity the transition may use, in (0, 1].
        step_ms: the controller's time step, ms: a fitted transition is a whole number of
            steps (at least one), so that inputs whose times are on the step stay on it
            (MT209). None: whole ms, at least 1.

    Each next motion's times are shifted so that its first pose lands at the end of the
    transition (a first pose at t > 0 loses its lead-in: the transition replaces it).

    Raises:
        MotionToolError: fewer than two inputs, different joints, a joint named twice, a
            ``nan``/``inf`` command, or a result past :data:`MAX_TIME_MS`.
    """
    _refuse_inputs(docs, transition_ms, max_velocity)
    first = docs[0]
    joints = first.joints
    limits = dict(max_velocity or {})
    unconstrained = tuple(j for j in joints if not math.isfinite(limits.get(j, math.inf)))
    joined = _Joined.of(first)
    transitions = []
    reordered = []
    for doc in docs[1:]:
        order = [doc.motion.joints.index(name) for name in joints]
        if order != list(range(len(joints))):
            reordered.append(doc.path)
        if transition_ms is None:
            start = _targets(doc.motion, order, 0)
            transition = _fitted(
                doc.path, joined.end_ms, joints, joined.last_row, start, limits, margin, step_ms
            )
        else:
            transition = Transition(doc.path, joined.end_ms, transition_ms, "", False)
        transitions.append(transition)
        joined.append(doc, order, transition.duration_ms)
    return Concatenated(
        joined.finish(),
        first.path,
        tuple(transitions),
        tuple(reordered),
        joined.dropped,
        unconstrained,
    )


@dataclass
class _Joined:
    """The motion :func:`concat` has joined so far.

    Attributes:
        first: the first input (its path and time style are the result's).
        eol: the first input's line end before ``\\n``: ``\\r`` (CRLF) or nothing.
        out: the bytes so far: the first input's header line, then each pose line after a
            ``\\n``, ended by ``eol`` (one buffer, grown in place: no line is held on its own).
        end_ms: the last pose's time, ms.
        last_row: (J,) the last pose's targets in the first input's column order, rad (m);
            NaN where it has ``*``.
        dropped: lines after a terminating blank line (ignored by Webots) left out.
        final_newline: whether the last input ends with a newline (so does the result).
    """

    first: MotionDocument
    eol: bytes
    out: io.BytesIO
    end_ms: int
    last_row: npt.NDArray[np.float64]
    dropped: int
    final_newline: bool

    @classmethod
    def of(cls, first: MotionDocument) -> _Joined:
        """The first input, as it is (but for its last line's end)."""
        base = PoseLines.of(first)
        out = io.BytesIO()
        out.write(base.header)
        write_lines(out, [with_eol(line, base.eol) for line in base.poses])
        end = int(first.motion.times_ms[-1])
        last_row = _targets(first.motion, list(range(first.motion.n_joints)), -1)
        return cls(first, base.eol, out, end, last_row, len(base.suffix), base.final_newline)

    def append(self, doc: MotionDocument, order: list[int], transition_ms: int) -> None:
        """``doc``'s poses, its columns in ``order`` (the input column of each of the first
        input's joints), its first pose ``transition_ms`` after the last pose so far."""
        new_times = _shifted_times(doc, self.end_ms + transition_ms)
        lines = PoseLines.of(doc)
        write_lines(
            self.out, _retimed_lines(lines, order, new_times, self.first.time_style, self.eol)
        )
        self.dropped += len(lines.suffix)
        self.final_newline = lines.final_newline
        self.end_ms = new_times[-1]
        self.last_row = _targets(doc.motion, order, -1)

    def finish(self) -> bytes:
        """End the joined file and give its bytes (the buffer's, not copied; nothing can be
        appended after)."""
        if self.final_newline:
            self.out.write(b"\n")
        elif self.eol:  # no final newline: the last line has no end
            self.out.truncate(self.out.tell() - len(self.eol))
        return self.out.getvalue()


def _targets(motion: Motion, order: list[int], pose: int) -> npt.NDArray[np.float64]:
    """(J,) the targets of pose ``pose`` of ``motion``, its columns in ``order``, rad (m); NaN
    where the pose has ``*``."""
    import numpy as np

    values = motion.values[pose, order]
    commanded = motion.commanded[pose, order]
    result: npt.NDArray[np.float64] = np.where(commanded, values, np.nan)
    return result


def _refuse_inputs(
    docs: Sequence[MotionDocument],
    transition_ms: int | None,
    max_velocity: Mapping[str, float] | None,
) -> None:
    """Raise :class:`MotionToolError` for what :func:`concat` cannot join: fewer than two
    inputs, neither a transition nor limits to fit one, a transition under 1 ms, a joint named
    twice, a ``nan``/``inf`` command, joints other than the first input's."""
    if len(docs) < 2:
        raise MotionToolError("concat needs two motions or more")
    if transition_ms is None and max_velocity is None:
        raise MotionToolError("give a transition time, or velocity limits to fit one")
    if transition_ms is not None and transition_ms < 1:
        raise MotionToolError(f"the transition must last at least 1 ms, got {transition_ms} ms")
    for doc in docs:
        refuse_duplicates(doc, "concat")
        refuse_non_finite(doc.motion, doc.result, "concatenating")
    for doc in docs[1:]:
        _refuse_other_joints(docs[0], doc)


def _refuse_other_joints(first: MotionDocument, doc: MotionDocument) -> None:
    """Raise :class:`MotionToolError` naming the joints ``doc`` lacks and has beyond
    ``first``'s, unless both have the same set."""
    want = set(first.joints)
    have = set(doc.joints)
    if have == want:
        return
    missing = [j for j in first.joints if j not in have]
    extra = [j for j in doc.joints if j not in want]
    parts = []
    if missing:
        parts.append("lacks " + ", ".join(missing))
    if extra:
        parts.append("has " + ", ".join(extra) + " that the first does not")
    raise MotionToolError(
        f"{doc.path} does not have the joints of {first.path}: it "
        + " and ".join(parts)
        + "; concat needs the same joints in every motion (add the missing columns, "
        "e.g. as '*')"
    )


def _fitted(
    into: str,
    start_ms: int,
    joints: Sequence[str],
    last_row: npt.NDArray[np.float64],
    first_row: npt.NDArray[np.float64],
    limits: Mapping[str, float],
    margin: float,
    step_ms: int | None,
) -> Transition:
    """The transition into ``into`` from ``last_row`` to ``first_row`` ((J,) rad or m, NaN
    where not commanded), starting at ``start_ms``: the shortest duration within ``margin`` x
    ``limits`` (rad/s, m/s), as :func:`fit_limits` fits two poses one step (``step_ms``, else
    1 ms) apart: whole steps, else whole ms."""
    import numpy as np

    retimed = fit_limits(
        [0, step_ms or 1],
        joints,
        np.vstack([last_row, first_row]),
        limits,
        margin=margin,
        step_ms=step_ms,
    )
    duration = int(retimed.times_ms[-1])
    joint = retimed.stretches[0].joint if retimed.stretches else ""
    return Transition(into, start_ms, duration, joint, True)


def _shifted_times(doc: MotionDocument, first_ms: int) -> list[int]:
    """``doc``'s pose times, ms, shifted so that its first pose is at ``first_ms``; raises
    :class:`MotionToolError` when the last is past :data:`MAX_TIME_MS`."""
    m = doc.motion
    shift = first_ms - int(m.times_ms[0])
    new_times = [int(t) + shift for t in m.times_ms]
    if new_times[-1] > MAX_TIME_MS:
        raise MotionToolError(
            f"joining {doc.path} would put its last pose at {new_times[-1]} ms, past the "
            f"longest time a .motion file can hold, {MAX_TIME_MS} ms"
        )
    return new_times


def _retimed_lines(
    lines: PoseLines, order: list[int], new_times: list[int], style: TimeStyle, eol: bytes
) -> list[bytes]:
    """``lines``' pose lines with the times ``new_times`` (ms, written in ``style``), the
    joint cells in ``order`` (input column of each output joint), each ended by ``eol``."""
    stamps = [format_time(t, style).encode("ascii") for t in new_times]
    poses = lines.poses
    if order != list(range(len(order))):
        columns = cell_columns(poses, 2 + len(order), lines.eol)
        if columns is None:
            columns = [list(c) for c in zip(*map(cell_tokens, poses), strict=True)]
        poses = join_columns([columns[0], columns[1], *(columns[2 + k] for k in order)], b"")
    return [
        set_time(line[:-1] if line.endswith(b"\r") else line, stamp) + eol
        for line, stamp in zip(poses, stamps, strict=True)
    ]
