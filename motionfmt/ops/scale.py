"""Scale a motion's excursions about a reference pose, clipped to the joint limits.

:func:`scale` changes only the cells whose value changes (spelt canonically, keeping their
leading white space); ``*`` stays ``*``. Limits come in as a plain mapping: no robot knowledge
here.
"""

from __future__ import annotations

import io
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.ops import _cells
from motiontool.motionfmt.ops._cells import (
    cell_columns,
    cell_tokens,
    header_eol,
    join_columns,
    odd_start,
    pose_block,
    pose_line_blocks,
    repair,
    replace_cells,
    respell,
    write_lines,
)
from motiontool.motionfmt.writer import format_values

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["Clip", "Scaled", "scale"]


@dataclass(frozen=True)
class Clip:
    """The cells of one joint that :func:`scale` clipped to its limits.

    Attributes:
        joint: the joint.
        count: how many cells.
        worst_excess: the largest distance of a scaled value beyond the limit, rad (m).
        unit: ``'rad'`` or ``'m'``.
        at_ms: the pose time of that worst cell, ms.
        bound: the limit it was clipped to, rad (m).
        side: ``'upper'`` or ``'lower'``: which limit ``bound`` is.
    """

    joint: str
    count: int
    worst_excess: float
    unit: str
    at_ms: int
    bound: float
    side: str


@dataclass(frozen=True)
class Scaled:
    """What :func:`scale` did.

    Attributes:
        document: the scaled document.
        amplitude: the factor K.
        about: the reference: ``'first'``, ``'zero'`` or a pose name.
        reference: (J,) the reference value of every column, rad (m); NaN for a column never
            commanded.
        changed: cells whose value changed.
        clips: per joint, the cells clipped to the limits (joints without any: not listed).
        unlimited: columns without limits (not clipped).
    """

    document: MotionDocument
    amplitude: float
    about: str
    reference: tuple[float, ...]
    changed: int
    clips: tuple[Clip, ...]
    unlimited: tuple[str, ...]

    @property
    def clipped(self) -> int:
        """How many cells were clipped, in all."""
        return sum(c.count for c in self.clips)


def _first_commanded(motion: Motion) -> npt.NDArray[np.float64]:
    import numpy as np

    c = motion.commanded
    has = c.any(axis=0)
    idx = np.argmax(c, axis=0)
    out: npt.NDArray[np.float64] = motion.values[idx, np.arange(c.shape[1])].copy()
    out[~has] = np.nan
    return out


def scale(
    doc: MotionDocument,
    amplitude: float,
    *,
    about: str = "first",
    limits: Mapping[str, tuple[float, float, str]] | None = None,
) -> Scaled:
    """Scale every joint's excursion: ``q' = ref + amplitude * (q - ref)``, clipped to limits.

    Args:
        doc: the document (not modified).
        amplitude: the factor K, finite and >= 0 (1 changes nothing, 0 holds the reference).
        about: the reference pose: ``'first'`` (each joint's first commanded value),
            ``'zero'`` (0 rad, the robot's zero pose), or the name of a pose of the file (its
            value; a joint that is ``*`` there uses its first commanded value).
        limits: ``{joint: (lower, upper, unit)}``, rad or m; a scaled value beyond is set to
            the bound and reported in :attr:`Scaled.clips`. Columns not in it are not clipped.

    ``*`` stays ``*``; cells whose value does not change keep their spelling.

    Raises:
        MotionToolError: a bad amplitude, an unknown pose name, a ``nan``/``inf`` command.
    """
    import numpy as np

    if not (math.isfinite(amplitude) and amplitude >= 0):
        raise MotionToolError(f"the amplitude must be a finite number >= 0, got {amplitude}")
    motion = doc.motion
    refuse_non_finite(motion, doc.result, "scaling")
    ref = _reference(doc, about)
    values = motion.values
    commanded = motion.commanded
    with np.errstate(invalid="ignore"):  # in place: one (P, J) array, not four
        new = values - ref
        new *= amplitude
        new += ref
    new[~commanded] = np.nan
    clips, unlimited = _clip(new, motion, limits or {})
    new += 0.0  # -0.0 -> 0.0
    changed = commanded & (new != values)
    document = repair(loads(_respelt(doc, new, changed), doc.path), new, commanded)
    return Scaled(
        document,
        amplitude,
        about,
        tuple(float(x) for x in ref),
        int(changed.sum()),
        tuple(clips),
        tuple(unlimited),
    )


def _reference(doc: MotionDocument, about: str) -> npt.NDArray[np.float64]:
    """(J,) the reference :func:`scale` scales about, rad (m): ``'first'``, ``'zero'`` or a
    pose name (see there); raises :class:`MotionToolError` for a name no pose has."""
    import numpy as np

    motion = doc.motion
    first = _first_commanded(motion)
    if about == "first":
        return first
    if about == "zero":
        return np.zeros(motion.n_joints)
    if about in motion.pose_names:
        p = motion.pose_names.index(about)
        ref: npt.NDArray[np.float64] = np.where(motion.commanded[p], motion.values[p], first)
        return ref
    shown = ", ".join(f"'{n}'" for n in motion.pose_names[:5])
    more = ", ..." if motion.n_poses > 5 else ""
    raise MotionToolError(
        f"no pose named '{about}' in {doc.path}; give first, zero, or a pose name ({shown}{more})"
    )


def _clip(
    new: npt.NDArray[np.float64],
    motion: Motion,
    limits: Mapping[str, tuple[float, float, str]],
) -> tuple[list[Clip], list[str]]:
    """Clip ``new`` ((P, J) scaled values of ``motion``'s columns, rad or m, NaN where not
    commanded) to ``limits`` in place; the :class:`Clip` of each joint with a cell beyond, and
    the joints ``limits`` does not have (not clipped)."""
    import numpy as np

    clips = []
    unlimited = []
    for j, name in enumerate(motion.joints):
        if name not in limits:
            unlimited.append(name)
            continue
        lower, upper, unit = limits[name]
        column = new[:, j]
        with np.errstate(invalid="ignore"):
            excess = np.maximum(column - upper, lower - column)
        out = np.flatnonzero(excess > 0)
        if out.shape[0]:
            worst = int(out[np.argmax(excess[out])])
            bound = upper if column[worst] > upper else lower
            clips.append(
                Clip(
                    name,
                    int(out.shape[0]),
                    float(excess[worst]),
                    unit,
                    int(motion.times_ms[worst]),
                    bound,
                    "upper" if column[worst] > upper else "lower",
                )
            )
            with np.errstate(invalid="ignore"):
                new[:, j] = np.clip(column, lower, upper)
    return clips, unlimited


def _respelt(
    doc: MotionDocument,
    new: npt.NDArray[np.float64],
    changed: npt.NDArray[np.bool_],
    *,
    columns: bool = True,
) -> bytes:
    """``doc``'s bytes with each cell where ``changed`` ((P, J) bool) spelt as its value in
    ``new`` ((P, J), rad or m), keeping its leading white space; every other byte as it was.

    ``columns``: blocks of plain pose lines are edited column by column
    (:func:`_respelt_columns`); False takes the line-by-line path below for every line: the
    reference the column path is tested against (the bytes are the same)."""
    import numpy as np

    data = doc.to_bytes()
    span = pose_block(data, doc.n_poses)
    header = data[: span[0] - 1]
    eol = header_eol(header)
    out = io.BytesIO()  # grown in place: the result's bytes are not copied again
    out.write(header)
    # A block of lines at a time: their cells, one bytes object each, are never all held.
    for lo, poses in pose_line_blocks(data, span, _cells.BLOCK_LINES, 0, doc.n_poses):
        block = slice(lo, lo + len(poses))
        edited = None
        if columns:
            edited = _respelt_columns(poses, new[block], changed[block], eol)
        if edited is None:
            edited = poses
            for p in np.flatnonzero(changed[block].any(axis=1)).tolist():
                tokens = cell_tokens(poses[p])
                cols = np.flatnonzero(changed[lo + p]).tolist()
                edited[p] = replace_cells(
                    poses[p], {2 + j: respell(tokens[2 + j], float(new[lo + p, j])) for j in cols}
                )
        write_lines(out, edited)
    out.write(data[span[1] :])
    return out.getvalue()


def _respelt_columns(
    poses: list[bytes], new: npt.NDArray[np.float64], changed: npt.NDArray[np.bool_], eol: bytes
) -> list[bytes] | None:
    """The pose lines ``poses`` (ending in ``eol``) edited as :func:`_respelt` edits them,
    column by column, where every line is plain and no value cell starts with white space
    (there is none to keep); None where that does not apply."""
    import numpy as np

    block = b"\n".join(poses)
    if odd_start(block):
        return None
    columns = cell_columns(poses, 2 + new.shape[1], eol, block)
    if columns is None:
        return None
    for j in np.flatnonzero(changed.any(axis=0)).tolist():
        rows = np.flatnonzero(changed[:, j])
        texts = format_values(new[rows, j])
        if rows.shape[0] == len(poses):
            columns[2 + j] = texts
            continue
        column = columns[2 + j]
        for p, text in zip(rows.tolist(), texts, strict=True):
            column[p] = text
    return join_columns(columns, eol)  # every line ends in ``eol`` (cell_columns checks it)
