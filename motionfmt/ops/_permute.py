"""Mirror's arithmetic on text: a number negated by its spelling, and the cells of plain pose
lines rearranged (and negated) by one numpy gather of the file's bytes.

A negated cell keeps its digits (``0.10`` -> ``-0.10``): Webots' ``strtod`` rounds correctly and
symmetrically about 0, so the text reads as exactly minus the number.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.lines import plain_cell_spans
from motiontool.motionfmt.ops._cells import lf_span

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["ODD_STARTS", "negate", "negate_column", "odd_start", "permute_cells"]


#: What a finite number's cell can start with, besides '-', '.' and a digit, in a file Webots
#: accepts: white space (sscanf skips it) and '+'.
ODD_STARTS = (b", ", b",+", b",\t", b",\x0b", b",\x0c")


def odd_start(block: bytes) -> bool:
    """Whether a cell of ``block`` (after the first of its line) starts with white space or
    '+' (a few ``in`` scans: a regex over a 26 MB file costs more than all of them)."""
    return any(odd in block for odd in ODD_STARTS)


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
