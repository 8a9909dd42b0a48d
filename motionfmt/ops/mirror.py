"""Mirror a motion left/right, keeping what is not changed as it was written.

:func:`mirror` swaps each left/right pair of columns and negates the joints whose mirror image
turns the other way, from a ``{joint: (partner, sign)}`` map
(:func:`motiontool.kinematics.mirror.mirror_map` derives it from a robot model). A negated cell
keeps its digits (``0.10`` -> ``-0.10``); ``mirror(mirror(x))`` commands what ``x`` does. Plain
pose lines are rearranged by one numpy gather of the file's bytes
(:func:`~motiontool.motionfmt.ops._permute.permute_cells`), other lines cell by cell.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.ops._cells import (
    PoseLines,
    cell_columns,
    cell_tokens,
    header_eol,
    join_columns,
    pose_block,
    refuse_duplicates,
    repair,
    replace_cells,
)
from motiontool.motionfmt.ops._permute import negate_column, odd_start, permute_cells
from motiontool.motionfmt.ops._result import ReadOnUse
from motiontool.motionfmt.reader import NO_VALUE_MARKER, token_spans

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["Mirrored", "mirror"]


@dataclass(frozen=True, eq=False)
class Mirrored(ReadOnUse):
    """What :func:`mirror` did.

    Attributes:
        data: the mirrored file's bytes.
        path: its name (the input's).
        swapped: column pairs whose values were exchanged, as (left-or-first, partner) names.
        negated: joints (output columns) whose values changed sign.
        renamed: (old, new) header names: a column whose partner is not in the file is renamed
            to the partner.
        unmapped: columns the map does not know (not motors of the robot): left unchanged.
    """

    data: bytes
    path: str
    swapped: tuple[tuple[str, str], ...]
    negated: tuple[str, ...]
    renamed: tuple[tuple[str, str], ...]
    unmapped: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class _MirrorPlan:
    """What :func:`mirror` writes: output column ``j`` (header name ``names[j]``) holds input
    column ``source[j]`` of ``motion`` times ``signs[j]``; ``flip`` (P, J) bool: the cells
    whose text is negated (:attr:`values` and :attr:`commanded`: the result, made when the
    per-cell path needs them)."""

    motion: Motion
    source: list[int]
    signs: list[int]
    names: list[str]
    flip: npt.NDArray[np.bool_]
    swapped: tuple[tuple[str, str], ...]
    renamed: tuple[tuple[str, str], ...]
    unmapped: tuple[str, ...]

    @property
    def joints(self) -> tuple[str, ...]:
        return self.motion.joints

    @property
    def values(self) -> npt.NDArray[np.float64]:
        """(P, J) float64, rad (m): the result's values."""
        import numpy as np

        sgn = np.asarray(self.signs, dtype=np.float64)
        return self.motion.values[:, self.source] * sgn + 0.0  # + 0.0: no '-0'

    @property
    def commanded(self) -> npt.NDArray[np.bool_]:
        """(P, J) bool: the result's commanded cells."""
        return self.motion.commanded[:, self.source]

    @property
    def moves(self) -> list[int]:
        """The output columns whose cells change: taken from another column, or negated."""
        return [
            j
            for j, (k, s) in enumerate(zip(self.source, self.signs, strict=True))
            if k != j or s < 0
        ]


def _mirror_plan(doc: MotionDocument, mapping: Mapping[str, tuple[str, int]]) -> _MirrorPlan:
    """The columns, signs and names of ``doc``'s mirror image (see :func:`mirror`)."""
    import numpy as np

    refuse_duplicates(doc, "mirroring")
    motion = doc.motion
    refuse_non_finite(motion, doc.result, "mirroring")
    joints = motion.joints
    col = {name: j for j, name in enumerate(joints)}
    source: list[int] = []
    signs: list[int] = []
    names: list[str] = []
    swapped: list[tuple[str, str]] = []
    renamed: list[tuple[str, str]] = []
    unmapped: list[str] = []
    for j, name in enumerate(joints):
        if name not in mapping:
            source.append(j)
            signs.append(1)
            names.append(name)
            unmapped.append(name)
            continue
        partner, sign = mapping[name]
        if sign not in (1, -1):
            raise MotionToolError(f"the mirror sign of {name} must be +1 or -1, got {sign}")
        if partner == name or partner not in col:
            source.append(j)
            names.append(partner)
            if partner != name:
                renamed.append((name, partner))
        else:
            source.append(col[partner])
            names.append(name)
            if j < col[partner]:
                swapped.append((name, partner))
        signs.append(sign)

    # Column by column (a negated one's cells only): no (P, J) array of values is made.
    flip = np.zeros((motion.n_poses, len(joints)), dtype=bool)
    for j, (k, sign) in enumerate(zip(source, signs, strict=True)):
        if sign > 0:
            continue
        column = motion.values[:, k]
        flip[:, j] = motion.commanded[:, k] & (column != 0.0)
        if np.any(flip[:, j] & (column == -NO_VALUE_MARKER)):
            raise MotionToolError(
                f"{doc.path}: a value of {-NO_VALUE_MARKER} negated is Webots' 'no value' "
                f"marker {NO_VALUE_MARKER}: the mirror cannot be written"
            )
    return _MirrorPlan(
        motion, source, signs, names, flip, tuple(swapped), tuple(renamed), tuple(unmapped)
    )


def _mirror_header(header: bytes, plan: _MirrorPlan) -> bytes:
    """The header line with the renamed columns' new names."""
    if not plan.renamed:
        return header
    spans = token_spans(header[:-1] if header.endswith(b"\r") else header)
    old = [name for name, _new in plan.renamed]
    for j in sorted((j for j, name in enumerate(plan.joints) if name in old), reverse=True):
        a, b = spans[2 + j]
        header = header[:a] + plan.names[j].encode("utf-8", "surrogateescape") + header[b:]
    return header


def _mirror_gather(doc: MotionDocument, plan: _MirrorPlan) -> bytes | None:
    """The bytes of ``doc``'s mirror image, the pose lines rearranged by :func:`permute_cells`;
    None where that does not apply (then the per-cell path of :func:`_mirror_bytes`)."""
    import numpy as np

    if not plan.moves:
        return None
    data = doc.to_bytes()
    start, stop = pose_block(data, doc.n_poses)
    header = data[: start - 1]
    negate = np.zeros((doc.n_poses, 2 + len(plan.source)), dtype=bool)
    negate[:, 2:] = plan.flip
    cells = [0, 1, *(2 + k for k in plan.source)]
    eol = header_eol(header)
    head = _mirror_header(header, plan) + b"\n"
    return permute_cells(
        data, doc.n_poses, eol, cells, negate, head, data[stop:], start=start, stop=stop
    )


def _mirror_bytes(doc: MotionDocument, plan: _MirrorPlan, *, gather: bool = True) -> bytes:
    """The bytes of ``doc``'s mirror image as ``plan`` says.

    ``gather``: plain pose lines are rearranged by :func:`_mirror_gather`; False takes the
    per-cell path below for every file: the reference the gather is tested against (the bytes
    are the same).
    """
    if gather:
        gathered = _mirror_gather(doc, plan)
        if gathered is not None:
            return gathered
    source, signs, moves = plan.source, plan.signs, plan.moves
    data = doc.to_bytes()
    lines = PoseLines.of_bytes(data, doc.n_poses)
    start, stop = pose_block(data, doc.n_poses)
    lines.header = _mirror_header(lines.header, plan)
    fast = plain = False
    if moves:
        block = data[start:stop]
        columns = cell_columns(lines.poses, 2 + len(source), lines.eol, block)
        if columns is None:  # lines Webots' tokenizer must split: one by one
            rows = [cell_tokens(line) for line in lines.poses]
            columns = [list(c) for c in zip(*rows, strict=True)]
            fast = False
        else:
            fast = True
        plain = fast and not odd_start(block)
        new_columns = list(columns)
        for j in moves:
            column = columns[2 + source[j]]
            if signs[j] < 0:
                column = negate_column(column, plan.flip[:, j].tolist(), plain)
            new_columns[2 + j] = column
        if fast:
            # Every line ends in ``eol``, the last one too: cell_columns checks it.
            lines.poses = join_columns(new_columns, lines.eol)
        else:
            lines.poses = [
                replace_cells(line, {2 + j: new_columns[2 + j][p] for j in moves})
                for p, line in enumerate(lines.poses)
            ]
    data = lines.to_bytes()
    if not (moves and fast and plain):
        # Cells negated by the slow path (white space, '+') are checked, and re-spelt if they
        # do not read as intended; the fast path's textual negation of a plain decimal number
        # is exact (strtod rounds correctly, symmetrically about 0).
        data = repair(loads(data, doc.path), plan.values, plan.commanded).to_bytes()
    return data


def mirror(doc: MotionDocument, mapping: Mapping[str, tuple[str, int]]) -> Mirrored:
    """Mirror ``doc`` left/right: ``q'[partner] = sign * q[joint]`` for every mapped column.

    Args:
        doc: the document (not modified).
        mapping: ``{joint: (partner, sign)}``, sign +1 or -1, symmetric (the partner maps back
            with the same sign); a centre joint is its own partner.

    Where both columns of a pair are in the file their cells are exchanged (the header stays);
    a column whose partner is missing is renamed to it. ``*`` stays ``*``, a zero is not
    negated, and a negated number keeps its digits.

    Raises:
        MotionToolError: a joint named twice, or a ``nan``/``inf`` command.
    """
    plan = _mirror_plan(doc, mapping)
    data = _mirror_bytes(doc, plan)
    negated = tuple(plan.names[j] for j in range(len(plan.names)) if plan.signs[j] < 0)
    return Mirrored(data, doc.path, plan.swapped, negated, plan.renamed, plan.unmapped)
