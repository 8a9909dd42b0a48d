"""A fast path for large, clean files: numpy's text reader parses the values in C.

It only ever answers for files where every pose line is plain ``time,name,number,...``: no
``*``, no empty cell, no blank line, no lone CR, no long line, no nan/inf/marker value, valid
times in strictly increasing order and none beyond the 2**31 - 1 ms a C ``int`` holds (Webots'
time arithmetic wraps there). For such lines ``numpy.loadtxt`` (Python's correctly rounded
``PyOS_string_to_double``, on the whole cell) and glibc's ``sscanf`` read the same doubles;
anything else makes this module answer ``None`` and the reader takes its exact line-by-line
path. A test checks that both paths agree.

The file is read a block of lines at a time (:data:`_BLOCK` bytes): the times and names are
read from the block's bytes with numpy, the values by ``loadtxt``, into arrays of their final
size (no copy of the whole file, no table of it all besides them), or checked and dropped
where the reader keeps no values (a check of the syntax only). Single-threaded: ``loadtxt``
holds Python's lock.
"""

from __future__ import annotations

import io
from collections.abc import Iterator
from typing import TYPE_CHECKING

from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.lines import plain_cell_spans
from motiontool.motionfmt.pose_names import PoseNames
from motiontool.motionfmt.units import TIME_FIELD_MS

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["read_clean_body", "read_values"]

_BLOCK = 1 << 18
"""Bytes of the file parsed at a time (cut after a newline)."""

_REFUSED = (b"*", b"\0", b"\x1c", b"\x1d", b"\x1e", b"\x1f", b"\x85", b"\xa0")
"""Bytes that send a file to the exact path wherever they are: ``*`` (no command), a NUL (it
ends a C string), and what ``loadtxt`` strips from a cell as whitespace (a Latin-1 character
for which ``str.isspace``) and Python's ``float`` and C's ``sscanf`` do not."""


def _gather(
    raw: npt.NDArray[np.uint8], starts: npt.NDArray[np.intp], ends: npt.NDArray[np.intp]
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.uint8]]:
    """The tokens ``raw[starts[i]:ends[i]]`` one after the other: their offsets (n + 1) into
    the bytes, and the bytes."""
    import numpy as np

    width = ends - starts
    offsets = np.zeros(width.shape[0] + 1, dtype=np.int64)
    np.cumsum(width, out=offsets[1:])
    at = np.repeat(starts - offsets[:-1], width) + np.arange(offsets[-1])
    return offsets, raw[at]


def _times(
    offsets: npt.NDArray[np.int64], raw: npt.NDArray[np.uint8], fields: int | None
) -> tuple[npt.NDArray[np.int64], int] | None:
    """Times in ms of n time tokens (``raw[offsets[i]:offsets[i + 1]]``) and how many ``:``
    each has, if every token is plain (1 to 5 digits, up to twice ``:`` and 1 to 5 digits) and
    all have the same number of ``:`` (``fields``, where a block before said)."""
    import numpy as np

    n = len(offsets) - 1
    if n == 0:
        return np.zeros(0, dtype=np.int64), fields or 0
    raw = raw[offsets[0] : offsets[-1]]
    offsets = offsets - offsets[0]
    colon = raw == ord(":")
    if not bool((colon | ((raw >= ord("0")) & (raw <= ord("9")))).all()):
        return None
    colons = np.flatnonzero(colon)
    k = len(colons) // n if fields is None else fields
    if k > 2 or len(colons) != k * n:
        return None
    # Token i's fields, if it has k colons: [start, colon), ..., [colon + 1, end). Colons
    # fall to the tokens in order; a token with more or fewer gets a field of width <= 0.
    at = colons.reshape(n, k)
    starts = np.concatenate([offsets[:-1, None], at + 1], axis=1)
    ends = np.concatenate([at, offsets[1:, None]], axis=1)
    width = ends - starts
    if not bool(((width >= 1) & (width <= 5)).all()):
        return None
    # A digit's place in its field: 10 ** (digits after it in that field).
    after = np.repeat(ends.ravel(), width.ravel()) - 1 - np.flatnonzero(~colon)
    value = np.zeros(len(raw), dtype=np.int64)
    value[~colon] = (raw[~colon] - ord("0")).astype(np.int64) * 10**after
    per_field = np.add.reduceat(value, starts.ravel()).reshape(n, k + 1)
    return per_field @ np.array(TIME_FIELD_MS[2 - k :], dtype=np.int64), k


def read_clean_body(
    data: bytes,
    n_joints: int,
    marker: float,
    max_line: int,
    start: int = 0,
    *,
    keep_values: bool = True,
) -> tuple[npt.NDArray[np.int64], PoseNames, npt.NDArray[np.float64] | None] | None:
    """Times (ms), pose names and values (P, J) of the pose lines in ``data[start:]`` (the file
    after its header line), or ``None``.

    Args:
        data, start: the file, and where its pose lines start.
        n_joints: J, from the header.
        marker: Webots' 'no value' number; a file holding it takes the exact path.
        max_line: the longest line (bytes, newline excluded) that Webots reads in one piece.
        keep_values: False: every value is read and checked, a block at a time, but none is
            kept (the values are ``None``; :func:`read_values` reads them again).
    """
    if start >= len(data) or n_joints < 1 or not _plain(data, start):
        return None
    import numpy as np

    values = None
    if keep_values:  # of its final size: a line a pose (a line too few or many: refused)
        n_poses = data.count(b"\n", start) + (not data.endswith(b"\n"))
        values = np.empty((n_poses, n_joints), dtype=np.float64)
    times: list[npt.NDArray[np.int64]] = []
    names = PoseNames()
    row, fields = 0, None
    for block in _blocks(data, start):
        got = _read_block(block, n_joints, max_line, fields)
        if got is None:
            return None
        block_times, fields, block_names, block_values = got
        if not bool(np.isfinite(block_values).all()) or bool((block_values == marker).any()):
            return None
        k = len(block_times)
        times.append(block_times)
        if values is not None:
            values[row : row + k] = block_values
        names.extend(block_names)
        row += k
    every = np.concatenate(times)
    if int(every.max()) > INT_MAX:
        return None  # Webots' int arithmetic wraps: the exact path wraps it too
    if bool((np.diff(every) <= 0).any()):
        return None
    return every, names, values


def read_values(
    data: bytes, n_joints: int, marker: float, max_line: int, start: int
) -> npt.NDArray[np.float64]:
    """The values, pose after pose (P * J), of a body that :func:`read_clean_body` has read
    (without keeping them): read again.

    Raises:
        RuntimeError: ``read_clean_body`` refuses the body (it did not before: a bug).
    """
    got = read_clean_body(data, n_joints, marker, max_line, start)
    if got is None or got[2] is None:
        raise RuntimeError("a motion read in bulk no longer reads in bulk")
    return got[2].reshape(-1)


def _blocks(data: bytes, start: int) -> Iterator[bytes]:
    """``data[start:]`` a block of whole lines at a time (:data:`_BLOCK` bytes or a line)."""
    while start < len(data):
        end = data.find(b"\n", min(start + _BLOCK, len(data)) - 1)
        end = len(data) if end < 0 else end + 1
        yield data[start:end]
        start = end


def _read_block(
    block: bytes, n_joints: int, max_line: int, fields: int | None
) -> tuple[npt.NDArray[np.int64], int, list[str], npt.NDArray[np.float64]] | None:
    """The times (ms), how many ``:`` they have, the pose names and the values (k, J) of the
    k lines of ``block``; None: a line only the exact path reads right (or longer than
    ``max_line`` bytes, newline excluded)."""
    import numpy as np

    text = np.frombuffer(block, dtype=np.uint8, count=len(block) - block.endswith(b"\n"))
    n_lines = block.count(b"\n", 0, text.shape[0]) + 1
    spans = plain_cell_spans(text, n_lines, n_joints + 2, np.int64)
    if spans is None:
        return None  # a cell too many, too few or empty (a blank line: none, an empty name)
    # From here no line is blank: loadtxt (which skips blank lines) reads a row a line.
    starts, stops = spans
    if int((stops[:, -1] - starts[:, 0]).max()) > max_line:
        return None  # Webots reads it in pieces
    got = _times(*_gather(text, starts[:, 0], stops[:, 0]), fields)
    if got is None:
        return None
    # Each name with the comma after it: the text of the names, a comma after each.
    names_text = _gather(text, starts[:, 1], stops[:, 1] + 1)[1]
    try:
        names = names_text.tobytes().decode("utf-8").split(",")[:-1]
        values = np.loadtxt(
            io.BytesIO(block),
            dtype=np.float64,
            delimiter=",",
            comments=None,
            usecols=range(2, n_joints + 2),
            ndmin=2,
        )
    except (UnicodeDecodeError, ValueError):  # loadtxt: a cell not a number, a lone CR
        return None
    return got[0], got[1], names, values


def _plain(data: bytes, start: int) -> bool:
    """No byte in ``data[start:]`` that only the exact path reads right (:data:`_REFUSED`); one
    ``memchr`` pass each. The rest needs no scan of the file: ``loadtxt`` refuses an empty
    number, text in one, Python's ``1_0`` (C reads 1) and a lone CR (an embedded newline to
    it); :func:`_read_block` (:func:`~motiontool.motionfmt.lines.plain_cell_spans`) a line with a
    cell too many, too few or empty."""
    return all(data.find(byte, start) < 0 for byte in _REFUSED)
