"""Mirror a motion left/right, keeping what is not changed as it was written.

:func:`mirror` swaps each left/right pair of columns and negates the joints whose mirror image
turns the other way, from a ``{joint: (partner, sign)}`` map
(:func:`motiontool.kinematics.mirror.mirror_map` derives it from a robot model). A negated cell
keeps its digits (``0.10`` -> ``-0.10``); ``mirror(mirror(x))`` commands what ``x`` does. Plain
pose lines are rearranged by one numpy gather of the file's bytes
(:func:`permute_cells`), other lines cell by cell: mirror's arithmetic on text is here too.

A negated cell keeps its digits (``0.10`` -> ``-0.10``): Webots' ``strtod`` rounds correctly and
symmetrically about 0, so the text reads as exactly minus the number.
"""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionToolError
from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.lines import plain_cell_spans
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.ops._cells import (
    ODD_STARTS,
    PoseLines,
    ReadOnUse,
    cell_columns,
    cell_tokens,
    header_eol,
    join_columns,
    lf_span,
    odd_start,
    pose_block,
    refuse_duplicates,
    repair,
    replace_cells,
)
from motiontool.motionfmt.reader import NO_VALUE_MARKER, token_spans

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = ["Mirrored", "mirror", "negate", "negate_column", "permute_cells"]


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


def negate_column(column: list[bytes], flags: list[bool], plain: bool) -> list[bytes]:
    """:func:`negate` on the cells where ``flags`` is True; ``plain``: every cell starts with
    '-', '.', a digit or '*' (then the fast paths)."""
    if not plain:
        return [negate(t) if f else t for t, f in zip(column, flags, strict=True)]
    if all(flags):  # every cell a nonzero number: prefix '-', then drop double minus signs
        block = (b"\n" + b"\n".join(column)).replace(b"\n", b"\n-").replace(b"\n--", b"\n")
        return block.split(b"\n")[1:]
    return [
        (t[1:] if t[0] == 45 else b"-" + t) if f else t  # 45: '-'
        for t, f in zip(column, flags, strict=True)
    ]


#: Input bytes rearranged per step of :func:`permute_cells`.
_GATHER_BYTES = 1 << 20


def permute_cells(
    data: bytes,
    n_lines: int,
    eol: bytes,
    cells: Sequence[int],
    negate: npt.NDArray[np.bool_],
    head: bytes = b"",
    tail: bytes = b"",
    *,
    start: int = 0,
    stop: int | None = None,
) -> bytes | None:
    """The pose block ``data[start:stop]`` with every line's cells rearranged, by a numpy gather
    of its bytes, between ``head`` and ``tail`` (the file's bytes are made once, written a
    block at a time into one buffer).

    Output cell ``k`` of line ``p`` is input cell ``cells[k]`` of that line, negated where
    ``negate[p, k]`` (shape (n_lines, len(cells)), bool; column 0, the time, never) as
    :func:`negate_column` does it on plain cells: a leading ``-`` is dropped, otherwise one is
    put in front. The bytes :func:`cell_columns`, :func:`negate_column` and :func:`join_columns`
    give, without a Python object per cell. None (the caller takes that path) unless every
    line is plain: ends as ``eol`` says, no NUL (:func:`lf_span`), exactly ``len(cells)``
    cells, none empty nor starting with white space or ``+`` (:data:`ODD_STARTS`). Those
    conditions imply the ones of that path's fast, plain case, where it is exact.
    """
    import numpy as np

    span = lf_span(data, n_lines, eol, start, len(data) if stop is None else stop)
    if span is None or bool(negate[:, 0].any()):
        return None
    plain, at, end = span
    if plain.count(b"\n", at, end) != n_lines - 1:
        return None
    order = np.asarray(cells, dtype=np.intp)
    # Lines are done about a megabyte of input at a time, each such block on its own: the
    # offsets, masks and index arrays stay that small (for the whole file they are several
    # times its size, and fresh memory is slow to touch).
    out = io.BytesIO()  # grown in place: its bytes are not copied again by getvalue
    out.write(head)
    line = 0
    while line < n_lines:
        cut = end if end - at <= _GATHER_BYTES else _block_end(plain, at, end)
        rows = plain.count(b"\n", at, cut) + 1
        gather = _Gather.of(plain[at:cut], rows, len(cells), eol)
        part = gather.permuted(order, negate[line : line + rows], line == 0, line + rows == n_lines)
        if part is None:
            return None
        out.write(part)
        line, at = line + rows, cut + 1
    out.write(tail)
    return out.getvalue()


def _block_end(plain: bytes, at: int, end: int) -> int:
    """Where a block of about :data:`_GATHER_BYTES` of the lines from ``at`` ends: the last
    line end within that many bytes, or the first after them for a longer line."""
    cut = plain.rfind(b"\n", at, at + _GATHER_BYTES)
    if cut < 0:
        cut = plain.find(b"\n", at + _GATHER_BYTES, end)
    return end if cut < 0 else cut


def _cell_spans(
    text: npt.NDArray[np.uint8], n_lines: int, n_cells: int, idx: type[np.signedinteger[Any]]
) -> tuple[npt.NDArray[np.signedinteger[Any]], npt.NDArray[np.signedinteger[Any]]] | None:
    """Where each cell of ``text`` (plain pose lines joined by ``\\n``) starts and stops, two
    (n_lines, n_cells) arrays of byte offsets (``stop`` past the cell's last byte); None unless
    every line has ``n_cells`` cells, none empty nor starting with white space or ``+``."""
    import numpy as np

    spans = plain_cell_spans(text, n_lines, n_cells, idx)
    if spans is None:
        return None
    odd = np.zeros(256, dtype=bool)
    odd[[start[1] for start in ODD_STARTS]] = True
    if bool(odd[text[spans[0]]].any()):
        return None  # a cell that starts with white space or '+'
    return spans


@dataclass(frozen=True)
class _Gather:
    """The input bytes of :func:`permute_cells` and the bytes its output adds.

    Attributes:
        buf: the plain block (``size`` bytes), then ``,-`` (a cell put after a separator with a
            minus sign), then the line end ``eol + \\n`` (whose start is the last line's end).
        size: the length of the plain block, bytes.
        end: the line end, ``eol + \\n``.
        eol: what ends the last line.
        idx: the offsets' dtype: int32 where the output and the input both stay below 2 GiB
            (halves the memory), int64 otherwise.
    """

    buf: npt.NDArray[np.uint8]
    size: int
    end: bytes
    eol: bytes
    idx: type[np.signedinteger[Any]]

    @classmethod
    def of(cls, plain: bytes, n_lines: int, n_cells: int, eol: bytes) -> _Gather:
        import numpy as np

        end = eol + b"\n"
        buf = np.frombuffer(plain + b",-" + end, dtype=np.uint8)
        bound = len(buf) + n_lines * (n_cells + len(end))
        idx: type[np.signedinteger[Any]] = np.int32 if bound < 2**31 else np.int64
        return cls(buf, len(plain), end, eol, idx)

    @property
    def text(self) -> npt.NDArray[np.uint8]:
        """The plain block's bytes."""
        return self.buf[: self.size]

    def permuted(
        self, order: npt.NDArray[np.intp], neg: npt.NDArray[np.bool_], opens: bool, closes: bool
    ) -> bytes | None:
        """The block's lines with their cells in ``order`` (negated where ``neg``), as
        :meth:`lines` writes them; None unless every line is plain (:func:`_cell_spans`)."""
        spans = _cell_spans(self.text, neg.shape[0], order.shape[0], self.idx)
        if spans is None:
            return None
        starts, stops = spans
        return self.lines(starts[:, order], stops[:, order], neg, opens=opens, closes=closes)

    def lines(
        self,
        starts: npt.NDArray[np.signedinteger[Any]],
        stops: npt.NDArray[np.signedinteger[Any]],
        neg: npt.NDArray[np.bool_],
        *,
        opens: bool,
        closes: bool,
    ) -> bytes:
        """Some lines of the output: ``starts``, ``stops`` (n, n_cells) the offsets of their
        input cells in output order (``starts`` is changed in place: past a dropped minus sign),
        ``neg`` (n, n_cells) which to negate; ``opens``: the first lines of the block (no line
        end before the first), ``closes``: the last (``eol`` after the last)."""
        import numpy as np

        n_cells = starts.shape[1]
        minus = self.text[starts] == 45  # 45: '-'
        starts += neg & minus  # drop the minus sign
        # Two pieces per output cell: what comes before it (nothing, the line end, ',' or
        # ',-'), then the cell's bytes; after the last line, its end (eol).
        piece_at = np.empty((starts.shape[0], n_cells, 2), dtype=self.idx)
        piece_len = np.empty((starts.shape[0], n_cells, 2), dtype=self.idx)
        piece_at[:, :, 0] = self.size
        piece_len[:, :, 0] = 1
        piece_len[:, :, 0] += neg & ~minus  # put a minus sign in
        piece_at[:, 0, 0] = self.size + 2
        piece_len[:, 0, 0] = len(self.end)
        if opens:
            piece_len[0, 0, 0] = 0
        piece_at[:, :, 1] = starts
        piece_len[:, :, 1] = stops - starts
        at = piece_at.ravel()
        length = piece_len.ravel()
        if closes:
            at = np.append(at, np.asarray(self.size + 2, dtype=self.idx))
            length = np.append(length, np.asarray(len(self.eol), dtype=self.idx))
        return _concat_ranges(self.buf, at, length, self.idx)


def _concat_ranges(
    buf: npt.NDArray[np.uint8],
    at: npt.NDArray[np.signedinteger[Any]],
    length: npt.NDArray[np.signedinteger[Any]],
    idx: type[np.signedinteger[Any]],
) -> bytes:
    """The ranges ``buf[at[i] : at[i] + length[i]]``, one after another: output byte ``k`` of
    range ``i`` is input byte ``at[i] + k``."""
    import numpy as np

    out_end = np.cumsum(length, dtype=idx)
    shift = at - (out_end - length)
    index = np.repeat(shift, length)
    index += np.arange(int(out_end[-1]), dtype=idx)
    return np.take(buf, index).tobytes()


def negate(token: bytes) -> bytes:
    """The cell that reads as minus ``token``'s number, with the same digits."""
    head = token[:1]
    if head == b"-":
        return token[1:]
    if head.isdigit() or head == b".":
        return b"-" + token
    body = token.lstrip()
    lead = token[: len(token) - len(body)]
    if body[:1] == b"-":
        return lead + body[1:]
    if body[:1] == b"+":
        return lead + b"-" + body[1:]
    return lead + b"-" + body
