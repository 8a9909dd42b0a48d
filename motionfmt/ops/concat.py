"""Concatenate motions: play them one after another, joined by transitions.

:func:`concat` joins motions with a transition from one's last pose to the next one's first pose
that is the shortest whole-ms duration within maxVelocity x margin
(:func:`~motiontool.motionfmt.transform.fit_limits`, the logic of ``retime --fit-limits``), or a
given one. The inputs' pose lines keep their spelling, but for their times.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.ops._cells import (
    PoseLines,
    cell_columns,
    cell_tokens,
    join_columns,
    refuse_duplicates,
    set_time,
    with_eol,
)
from motiontool.motionfmt.transform import DEFAULT_MARGIN, MAX_TIME_MS, fit_limits
from motiontool.motionfmt.writer import format_time

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


@dataclass(frozen=True)
class Concatenated:
    """What :func:`concat` did.

    Attributes:
        document: the joined document (the first input's header and lines first).
        transitions: one per joint between two inputs.
        reordered: inputs whose columns were put in the first input's order.
        dropped_lines: lines after a terminating blank line (ignored by Webots) left out.
        unconstrained: joints without a velocity limit (not constrained by the fit).
    """

    document: MotionDocument
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

    Each next motion's times are shifted so that its first pose lands at the end of the
    transition (a first pose at t > 0 loses its lead-in: the transition replaces it).

    Raises:
        MotionToolError: fewer than two inputs, different joints, a joint named twice, a
            ``nan``/``inf`` command, or a result past :data:`MAX_TIME_MS`.
    """
    import numpy as np

    if len(docs) < 2:
        raise MotionToolError("concat needs two motions or more")
    if transition_ms is None and max_velocity is None:
        raise MotionToolError("give a transition time, or velocity limits to fit one")
    if transition_ms is not None and transition_ms < 1:
        raise MotionToolError(f"the transition must last at least 1 ms, got {transition_ms} ms")
    first = docs[0]
    joints = first.joints
    for doc in docs:
        refuse_duplicates(doc, "concat")
        refuse_non_finite(doc.motion, doc.result, "concatenating")
    want = set(joints)
    for doc in docs[1:]:
        have = set(doc.joints)
        if have != want:
            missing = [j for j in joints if j not in have]
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
    limits = dict(max_velocity or {})
    unconstrained = tuple(j for j in joints if not math.isfinite(limits.get(j, math.inf)))

    base = PoseLines.of(first)
    eol = base.eol
    out_poses = [with_eol(line, eol) for line in base.poses]
    dropped = len(base.suffix)
    motion = first.motion
    end = int(motion.times_ms[-1])
    last_row = np.where(motion.commanded[-1], motion.values[-1], np.nan)
    transitions = []
    reordered = []
    style = first.time_style
    final_newline = base.final_newline
    for doc in docs[1:]:
        m = doc.motion
        order = [m.joints.index(name) for name in joints]
        if order != list(range(len(joints))):
            reordered.append(doc.path)
        values = m.values[:, order]
        commanded = m.commanded[:, order]
        start = np.where(commanded[0], values[0], np.nan)
        if transition_ms is None:
            retimed = fit_limits(
                [0, 1], joints, np.vstack([last_row, start]), limits, margin=margin
            )
            duration = int(retimed.times_ms[-1])
            joint = retimed.stretches[0].joint if retimed.stretches else ""
            fitted = True
        else:
            duration, joint, fitted = transition_ms, "", False
        shift = end + duration - int(m.times_ms[0])
        new_times = [int(t) + shift for t in m.times_ms]
        if new_times[-1] > MAX_TIME_MS:
            raise MotionToolError(
                f"joining {doc.path} would put its last pose at {new_times[-1]} ms, past the "
                f"longest time a .motion file can hold, {MAX_TIME_MS} ms"
            )
        transitions.append(Transition(doc.path, end, duration, joint, fitted))
        lines = PoseLines.of(doc)
        stamps = [format_time(t, style).encode("ascii") for t in new_times]
        poses = lines.poses
        if order != list(range(len(joints))):
            columns = cell_columns(poses, 2 + len(joints), lines.eol)
            if columns is None:
                columns = [list(c) for c in zip(*map(cell_tokens, poses), strict=True)]
            poses = join_columns([columns[0], columns[1], *(columns[2 + k] for k in order)], b"")
        ends = [eol] * len(poses)
        out_poses.extend(
            set_time(line[:-1] if line.endswith(b"\r") else line, stamp) + end
            for line, stamp, end in zip(poses, stamps, ends, strict=True)
        )
        dropped += len(lines.suffix)
        final_newline = lines.final_newline
        end = new_times[-1]
        last_row = np.where(commanded[-1], values[-1], np.nan)
    if not final_newline:
        out_poses[-1] = with_eol(out_poses[-1], b"")
    out = PoseLines(base.header, out_poses, [], eol, final_newline)
    document = loads(out.to_bytes(), first.path)
    return Concatenated(document, tuple(transitions), tuple(reordered), dropped, unconstrained)
