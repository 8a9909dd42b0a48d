"""How Webots cuts a ``.motion`` file into lines and cells: ``fgets`` and ``strtok``.

``wbu_motion_new`` reads the file with ``fgets(buffer, 4096, file)`` (at most 4095 bytes a
piece: a longer line is read as several) and cuts each piece with ``strtok(piece, ",\\n\\r")``,
which skips empty cells and ends at a NUL byte. ``docs/webots-format.md`` is the reference.

Columns are 1-based byte offsets in the physical line (lines split on ``\\n``).
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import TYPE_CHECKING, NamedTuple

from motiontool.motionfmt.diagnostics import CUT_LINE

if TYPE_CHECKING:
    from typing import Any

    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt._read_state import ReadState

__all__ = [
    "FGETS_PIECE",
    "Piece",
    "PoseLine",
    "check_utf8",
    "decode_name",
    "fgets_pieces",
    "plain_cell_spans",
    "separator_hint",
    "show",
    "token_spans",
]

FGETS_PIECE = 4095
"""Webots reads lines with ``fgets(buffer, 4096, file)``: at most 4095 bytes a piece."""

_TOKEN = re.compile(rb"[^,\r\n]+")


def token_spans(piece: bytes) -> list[tuple[int, int]]:
    """(start, end) 0-based byte offsets of the tokens ``strtok(piece, ",\\n\\r")`` finds:
    the one cell tokeniser of motiontool (a C string ends at a NUL byte)."""
    nul = piece.find(b"\0")
    if nul >= 0:
        piece = piece[:nul]
    if b"\r" in piece or b"\n" in piece:
        return [m.span() for m in _TOKEN.finditer(piece)]
    spans = []  # only ',' separates: the tokens are the non-empty pieces between commas
    start = 0
    for part in piece.split(b","):
        end = start + len(part)
        if end > start:
            spans.append((start, end))
        start = end + 1
    return spans


def plain_cell_spans(
    text: npt.NDArray[np.uint8], n_lines: int, n_cells: int, idx: type[np.signedinteger[Any]]
) -> tuple[npt.NDArray[np.signedinteger[Any]], npt.NDArray[np.signedinteger[Any]]] | None:
    """:func:`token_spans` of many lines at once, where they are plain: where each cell of
    ``text`` (``n_lines`` lines joined by ``\\n``, without CR or NUL) starts and stops, two
    (n_lines, n_cells) arrays of byte offsets in ``text`` (``stop`` past the cell's last byte,
    dtype ``idx``); None unless every line has ``n_cells`` cells and none is empty (then
    ``strtok`` finds exactly those)."""
    import numpy as np

    seps = np.flatnonzero((text == 44) | (text == 10))  # 44: ',', 10: '\n'
    if seps.shape[0] != n_lines * n_cells - 1:
        return None
    newline = text[seps] == 10
    if int(np.count_nonzero(newline)) != n_lines - 1:
        return None
    if not bool(newline[n_cells - 1 :: n_cells].all()):
        return None  # a line with more or fewer cells than the others
    bounds = np.empty(n_lines * n_cells + 1, dtype=idx)
    bounds[0] = -1
    bounds[1:-1] = seps
    bounds[-1] = text.shape[0]
    starts = (bounds[:-1] + 1).reshape(n_lines, n_cells)
    stops = bounds[1:].reshape(n_lines, n_cells)
    if int((stops - starts).min()) < 1:
        return None  # an empty cell
    return starts, stops


def show(token: bytes, limit: int = 40) -> str:
    """A token as a quoted, printable string for messages (non-UTF-8 bytes escaped)."""
    text = token.decode("utf-8", "backslashreplace")
    if len(text) > limit:
        text = text[: limit - 3] + "..."
    return repr(text)


SEPARATORS = frozenset(b"%;\t |")
"""Bytes (as ints) that people separate cells with and Webots does not: ``strtok`` splits on
commas only (and ends of line), so a line cut by one of them reads as one cell."""


def separator_hint(cell: bytes, start: int, example: str) -> str | None:
    """The hint for a cell whose byte ``start`` is one of :data:`SEPARATORS` followed by more
    text (the line is separated by it, not by commas), else None; ``example`` is how the line
    is written."""
    if start + 1 >= len(cell) or cell[start] not in SEPARATORS:
        return None
    return (
        f"the cells are separated by {show(cell[start : start + 1])}: Webots separates them by"
        f" commas only, so this line is one cell; write {example}"
    )


def decode_name(raw: bytes) -> str:
    """Names keep undecodable bytes as surrogates, so they survive a round trip."""
    return raw.decode("utf-8", "surrogateescape")


class Piece(NamedTuple):
    """What one ``fgets`` call returns: part of a physical line."""

    line: int  # 1-based physical line
    col0: int  # byte offset of the piece in its physical line
    data: bytes  # without the newline


class PoseLine:
    """A pose line's piece cut into its tokens, for the exact path.

    Attributes:
        raw: the piece's bytes; line: its 1-based physical line.
        spans, tokens: the tokens (:func:`token_spans`) and their bytes.
        c0: add to a 0-based offset in the piece to get a 1-based column in the line.
    """

    __slots__ = ("c0", "line", "raw", "spans", "tokens")

    def __init__(self, piece: Piece, spans: list[tuple[int, int]]) -> None:
        self.raw = piece.data
        self.line = piece.line
        self.c0 = piece.col0 + 1
        self.spans = spans
        self.tokens = [piece.data[a:b] for a, b in spans]


def _physical_lines(data: bytes) -> Iterator[tuple[bytes, bool]]:
    """Each line of ``data`` (without its ``\\n``) and whether a newline ends it, as
    :attr:`ReadState.lines` holds them, found one at a time (none after a final newline)."""
    pos = 0
    while True:
        end = data.find(b"\n", pos)
        if end < 0:
            if pos < len(data):
                yield data[pos:], False
            return
        yield data[pos:end], True
        pos = end + 1


def fgets_pieces(state: ReadState) -> Iterator[Piece]:
    """The lines as Webots' ``fgets`` returns them, with long lines cut into pieces (MT111);
    read as they are asked for (a large file read in bulk only has its header line read)."""
    for i, (content, has_newline) in enumerate(_physical_lines(state.data)):
        full_length = len(content) + (1 if has_newline else 0)
        if full_length <= FGETS_PIECE:
            yield Piece(i + 1, 0, content)
            continue
        state.report(
            CUT_LINE,
            i + 1,
            FGETS_PIECE + 1,
            f"line is {len(content)} bytes long; Webots reads at most {FGETS_PIECE - 1} bytes"
            f" of a line (plus its newline) at a time and reads the rest as a new line",
            "split the motion into fewer joints, or shorten pose names and numbers",
            end_column=len(content) + 1,
        )
        for start in range(0, full_length, FGETS_PIECE):
            yield Piece(i + 1, start, content[start : start + FGETS_PIECE])


def check_utf8(state: ReadState) -> None:
    """MT208 at the first byte of each line that is not UTF-8."""
    if state.data.isascii():  # no copy of the file to find that out
        return
    try:
        state.data.decode("utf-8")
    except UnicodeDecodeError:
        pass
    else:
        return
    for i, content in enumerate(state.lines):
        try:
            content.decode("utf-8")
        except UnicodeDecodeError as exc:
            bad = content[exc.start]
            where = "a joint name" if i == 0 else "this line"
            consequence = (
                "; no motor name will match it" if i == 0 else "; other tools may not read it"
            )
            state.report(
                "MT208",
                i + 1,
                exc.start + 1,
                f"byte 0x{bad:02X} in {where} is not UTF-8{consequence}",
                "save the file as UTF-8",
            )
