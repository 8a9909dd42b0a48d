"""A document's lines and cells as bytes, as the operations of this package edit them.

An operation keeps every line and cell it does not change as it was written (spacing, ``+0.1``,
digits, CRLF, a missing final newline): it works on the bytes of the lines, split on ``,`` where
a line is plain (the fast path), with Webots' tokenizer
(:func:`~motiontool.motionfmt.reader.token_spans`) where it is not (empty cells, a NUL, a stray
``\r``). :func:`repair` is the safety net under the textual edits: it re-spells any cell that
does not read as intended. :func:`refuse_duplicates` is the check every column-wise edit makes
first, :func:`odd_start` the test for cells that take the slow path, and :class:`ReadOnUse` what
an operation gives back.
"""

from __future__ import annotations

import functools
import io
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from motiontool.errors import MotionToolError
from motiontool.motionfmt.document import MotionDocument, loads
from motiontool.motionfmt.reader import token_spans
from motiontool.motionfmt.writer import format_value

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt


__all__ = [
    "BLOCK_LINES",
    "ODD_STARTS",
    "PoseLines",
    "ReadOnUse",
    "cell_columns",
    "cell_tokens",
    "header_eol",
    "join_columns",
    "lf_block",
    "lf_span",
    "odd_start",
    "pose_block",
    "pose_line_blocks",
    "refuse_duplicates",
    "repair",
    "replace_cells",
    "respell",
    "set_time",
    "split_cells",
    "with_eol",
    "write_lines",
]


@dataclass
class PoseLines:
    """A document's physical lines: header, one line per pose, the ignored rest.

    ``eol`` is ``b"\\r"`` for a CRLF file (lines are split on ``\\n``), ``b""`` otherwise.
    """

    header: bytes
    poses: list[bytes]
    suffix: list[bytes]
    eol: bytes
    final_newline: bool

    @classmethod
    def of(cls, doc: MotionDocument) -> PoseLines:
        return cls.of_bytes(doc.to_bytes(), doc.n_poses)

    @classmethod
    def of_bytes(cls, data: bytes, n_poses: int) -> PoseLines:
        """The lines of a document's bytes ``data`` that has ``n_poses`` pose lines."""
        final = data.endswith(b"\n")
        lines = data.split(b"\n")
        if final:
            lines.pop()
        eol = header_eol(lines[0])
        return cls(lines[0], lines[1 : n_poses + 1], lines[n_poses + 1 :], eol, final)

    def to_bytes(self) -> bytes:
        body = b"\n".join([self.header, *self.poses, *self.suffix])
        return body + b"\n" if self.final_newline else body


def header_eol(header: bytes) -> bytes:
    """What ends every line of a file whose header line (without its ``\\n``) is ``header``,
    before the ``\\n``: ``\\r`` for a CRLF file, nothing otherwise."""
    return b"\r" if header.endswith(b"\r") else b""


def write_lines(out: io.BytesIO, lines: list[bytes]) -> None:
    """Write each of ``lines`` after a ``\\n`` (the line before it ends there), joined
    :data:`BLOCK_LINES` at a time."""
    for a in range(0, len(lines), BLOCK_LINES):
        out.write(b"\n")
        out.write(b"\n".join(lines[a : a + BLOCK_LINES]))


BLOCK_LINES = 8192
"""Pose lines the operations that stream their result (trim, retime, scale, concat) handle at
a time: split from the input, re-spelt and joined this many at once, never all of them (read
as ``_cells.BLOCK_LINES`` where it is used, so that a test can make the blocks small)."""


def pose_block(data: bytes, n_poses: int) -> tuple[int, int]:
    """(start, stop): where the ``n_poses`` pose lines of a document's bytes ``data`` are, from
    the first byte of line 2 to the end of the last pose line (newline excluded); found
    without splitting the lines (one ``count``, or a ``find`` per line where lines follow the
    poses)."""
    start = data.index(b"\n") + 1
    newlines = data.count(b"\n", start)
    if newlines == n_poses and data.endswith(b"\n"):
        return start, len(data) - 1
    if newlines == n_poses - 1 and not data.endswith(b"\n"):
        return start, len(data)
    stop = start
    for _ in range(n_poses):  # lines after a blank line follow the poses
        stop = data.index(b"\n", stop) + 1
    return start, stop - 1


def pose_line_blocks(
    data: bytes, span: tuple[int, int], size: int, first: int, stop_at: int
) -> Iterator[tuple[int, list[bytes]]]:
    """Pose lines ``first`` to ``stop_at - 1`` (0-based) of a document's bytes ``data`` whose
    pose lines are at ``span`` (:func:`pose_block`), ``size`` at a time: (the index of a
    block's first line, its lines split from the bytes). The lines are found one ``find`` at a
    time: neither all lines nor an index of them is held."""
    start, stop = span
    at = start  # where the next line starts
    for _ in range(first):
        at = data.index(b"\n", at) + 1
    for a in range(first, stop_at, size):
        end = at
        for _ in range(min(size, stop_at - a)):
            end = data.find(b"\n", end, stop) + 1 or stop + 1
        yield a, data[at : end - 1].split(b"\n")
        at = end


def split_cells(line: bytes) -> list[bytes] | None:
    """The cells of a pose line split on ``,`` (the end's ``\\r`` kept on the last cell's
    outside: see :func:`_join_cells`), or None when the line needs Webots' tokenizer (empty
    cells, a NUL, a ``\\r`` inside)."""
    body = line[:-1] if line.endswith(b"\r") else line
    if b"\r" in body or b"\0" in body:
        return None
    parts = body.split(b",")
    return None if b"" in parts else parts


def replace_cells(line: bytes, changes: Mapping[int, bytes]) -> bytes:
    """``line`` with its cells (0: time, 1: name, 2..: values) replaced as ``changes`` says."""
    if not changes:
        return line
    parts = split_cells(line)
    if parts is not None:
        for k, text in changes.items():
            parts[k] = text
        return b",".join(parts) + (b"\r" if line.endswith(b"\r") else b"")
    spans = token_spans(line)
    out = line
    for k in sorted(changes, reverse=True):
        a, b = spans[k]
        out = out[:a] + changes[k] + out[b:]
    return out


def cell_tokens(line: bytes) -> list[bytes]:
    """Every cell of a pose line as Webots' tokenizer finds it."""
    parts = split_cells(line)
    if parts is not None:
        return parts
    return [line[a:b] for a, b in token_spans(line)]


def lf_block(block: bytes, n_lines: int, eol: bytes) -> bytes | None:
    """``block`` (``n_lines`` pose lines joined with ``\\n``) without its ``\\r``s, or None
    when a line needs Webots' tokenizer for its ends or a NUL (a stray ``\\r``, an end unlike
    ``eol``). Empty cells are the callers' to find: a two-byte ``in`` scan of 26 MB takes
    30-40 ms, a one-byte one (``memchr``) 2 ms."""
    span = lf_span(block, n_lines, eol, 0, len(block))
    return None if span is None else span[0]


def lf_span(
    data: bytes, n_lines: int, eol: bytes, start: int, stop: int
) -> tuple[bytes, int, int] | None:
    """:func:`lf_block` of ``data[start:stop]`` as ``(bytes, start, stop)``, where those bytes
    hold the block from ``start`` to ``stop``: ``data`` itself for LF lines (no copy of a long
    file's block), a copy without its ``\\r``s for CRLF ones."""
    if eol:
        block = data[start:stop]
        if block.count(b"\r") != n_lines or not block.endswith(b"\r"):
            return None
        if block.count(b"\r\n") != n_lines - 1:
            return None
        block = block.replace(b"\r", b"")
        return None if b"\0" in block else (block, 0, len(block))
    if data.find(b"\r", start, stop) >= 0 or data.find(b"\0", start, stop) >= 0:
        return None
    return data, start, stop


def cell_columns(
    poses: list[bytes], n_cells: int, eol: bytes, block: bytes | None = None
) -> list[list[bytes]] | None:
    """The cells of every pose line, column by column (``n_cells`` columns, time first), in
    one ``split`` of the whole block; None when a line needs Webots' tokenizer (empty cells,
    a NUL, a stray ``\\r``, an end unlike ``eol``). ``block``: the lines already joined with
    ``\\n``, when the caller has them (a slice of the file's bytes)."""
    lf = lf_block(b"\n".join(poses) if block is None else block, len(poses), eol)
    if lf is None or b",," in lf or b",\n" in lf or b"\n," in lf:
        return None
    if lf.startswith(b",") or lf.endswith(b","):
        return None
    flat = lf.replace(b"\n", b",").split(b",")
    if len(flat) != n_cells * len(poses):
        return None
    return [flat[k::n_cells] for k in range(n_cells)]


def join_columns(columns: list[list[bytes]], eol: bytes) -> list[bytes]:
    """Pose lines from cells given column by column (see :func:`cell_columns`)."""
    lines = list(map(b",".join, zip(*columns, strict=True)))
    return [line + eol for line in lines] if eol else lines


def set_time(line: bytes, token: bytes) -> bytes:
    """``line`` with its time cell (which never has white space: MT105) replaced by ``token``."""
    return token + line[line.index(b",") :]


def respell(token: bytes, value: float) -> bytes:
    """``value`` spelt canonically, keeping ``token``'s leading white space."""
    lead = token[: len(token) - len(token.lstrip())]
    return lead + format_value(value).encode("ascii")


def with_eol(line: bytes, eol: bytes) -> bytes:
    return (line[:-1] if line.endswith(b"\r") else line) + eol


def refuse_duplicates(doc: MotionDocument, what: str) -> None:
    seen: set[str] = set()
    for name in doc.joints:
        if name in seen:
            raise MotionToolError(
                f"{doc.path}: joint '{name}' is named twice (MT205); {what} needs each joint "
                "once: remove or rename the extra column first"
            )
        seen.add(name)


def repair(
    doc: MotionDocument,
    values: npt.NDArray[np.float64],
    commanded: npt.NDArray[np.bool_],
) -> MotionDocument:
    """Re-spell canonically every cell of ``doc`` that does not read as ``values`` (NaN and
    ``commanded`` False: ``*``); a safety net under the textual edits."""
    import numpy as np

    got = doc.motion
    same = (got.values == values) | (~got.commanded & ~commanded)
    same &= got.commanded == commanded
    for p, j in np.argwhere(~same).tolist():
        doc.set_value(p, j, float(values[p, j]) if commanded[p, j] else math.nan)
    return doc


#: What a finite number's cell can start with, besides '-', '.' and a digit, in a file Webots
#: accepts: white space (sscanf skips it) and '+'.
ODD_STARTS = (b", ", b",+", b",\t", b",\x0b", b",\x0c")


def odd_start(block: bytes) -> bool:
    """Whether a cell of ``block`` (after the first of its line) starts with white space or
    '+' (a few ``in`` scans: a regex over a 26 MB file costs more than all of them)."""
    return any(odd in block for odd in ODD_STARTS)


class ReadOnUse:
    """A mixin for an operation's (frozen) result dataclass that has ``data`` (the result's
    bytes) and ``path`` (its name)."""

    data: bytes
    path: str

    @functools.cached_property
    def document(self) -> MotionDocument:
        """The result, read as a document (on first use)."""
        return loads(self.data, self.path)
