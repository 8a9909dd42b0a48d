"""Mirror's arithmetic on text: a number negated by its spelling, and the cells of plain pose
lines rearranged (and negated) by one numpy gather of the file's bytes.

A negated cell keeps its digits (``0.10`` -> ``-0.10``): Webots' ``strtod`` rounds correctly and
symmetrically about 0, so the text reads as exactly minus the number.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.ops._cells import lf_block

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
    block: bytes,
    n_lines: int,
    eol: bytes,
    cells: Sequence[int],
    negate: npt.NDArray[np.bool_],
) -> bytes | None:
    """The pose block with every line's cells rearranged, by a numpy gather of its bytes.

    Output cell ``k`` of line ``p`` is input cell ``cells[k]`` of that line, negated where
    ``negate[p, k]`` (shape (n_lines, len(cells)), bool; column 0, the time, never) as
    :func:`negate_column` does it on plain cells: a leading ``-`` is dropped, otherwise one is
    put in front. The bytes :func:`cell_columns`, :func:`negate_column` and :func:`join_columns`
    give, without a Python object per cell. None (the caller takes that path) unless every
    line is plain: ends as ``eol`` says, no NUL (:func:`lf_block`), exactly ``len(cells)``
    cells, none empty nor starting with white space or ``+`` (:data:`ODD_STARTS`). Those
    conditions imply the ones of that path's fast, plain case, where it is exact.
    """
    import numpy as np

    plain = lf_block(block, n_lines, eol)
    if plain is None or bool(negate[:, 0].any()):
        return None
    n_cells = len(cells)
    size = len(plain)
    end = eol + b"\n"
    # Bytes the output has and the input may not: ',' and ',-' (a cell put after a separator
    # with a minus sign), then the line end (whose start is the last line's end, ``eol``).
    buf = np.frombuffer(plain + b",-" + end, dtype=np.uint8)
    text = buf[:size]
    seps = np.flatnonzero((text == 44) | (text == 10))  # 44: ',', 10: '\n'
    if seps.shape[0] != n_lines * n_cells - 1:
        return None
    newline = text[seps] == 10
    if int(np.count_nonzero(newline)) != n_lines - 1:
        return None
    if not bool(newline[n_cells - 1 :: n_cells].all()):
        return None  # a line with more or fewer cells than the others
    # int32 offsets where the output and the input both stay below 2 GiB (halves the memory).
    bound = len(buf) + n_lines * (n_cells + len(end))
    idx: type[np.signedinteger[Any]] = np.int32 if bound < 2**31 else np.int64
    bounds = np.empty(n_lines * n_cells + 1, dtype=idx)
    bounds[0] = -1
    bounds[1:-1] = seps
    bounds[-1] = size
    starts = (bounds[:-1] + 1).reshape(n_lines, n_cells)
    stops = bounds[1:].reshape(n_lines, n_cells)
    if int((stops - starts).min()) < 1:
        return None  # an empty cell
    odd = np.zeros(256, dtype=bool)
    odd[[start[1] for start in ODD_STARTS]] = True
    if bool(odd[text[starts]].any()):
        return None  # a cell that starts with white space or '+'
    order = np.asarray(cells, dtype=np.intp)
    # Lines are done about a megabyte of input at a time: the index arrays stay small (one
    # index for the whole file is 4 bytes per byte, and fresh memory is slow to touch).
    rows = max(1, _GATHER_BYTES * n_lines // max(size, 1))
    parts = []
    for a in range(0, n_lines, rows):
        b = min(a + rows, n_lines)
        neg = negate[a:b]
        first = starts[a:b, order]
        last = stops[a:b, order]
        minus = text[first] == 45  # 45: '-'
        first += neg & minus  # drop the minus sign
        # Two pieces per output cell: what comes before it (nothing, the line end, ',' or
        # ',-'), then the cell's bytes; after the last line, its end (eol).
        piece_at = np.empty((b - a, n_cells, 2), dtype=idx)
        piece_len = np.empty((b - a, n_cells, 2), dtype=idx)
        piece_at[:, :, 0] = size
        piece_len[:, :, 0] = 1
        piece_len[:, :, 0] += neg & ~minus  # put a minus sign in
        piece_at[:, 0, 0] = size + 2
        piece_len[:, 0, 0] = len(end)
        if a == 0:
            piece_len[0, 0, 0] = 0
        piece_at[:, :, 1] = first
        piece_len[:, :, 1] = last - first
        at = piece_at.ravel()
        length = piece_len.ravel()
        if b == n_lines:
            at = np.append(at, np.asarray(size + 2, dtype=idx))
            length = np.append(length, np.asarray(len(eol), dtype=idx))
        # Concatenated ranges: output byte i of a piece is input byte at + i.
        out_end = np.cumsum(length, dtype=idx)
        shift = at - (out_end - length)
        index = np.repeat(shift, length)
        index += np.arange(int(out_end[-1]), dtype=idx)
        parts.append(np.take(buf, index).tobytes())
    return b"".join(parts)


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
