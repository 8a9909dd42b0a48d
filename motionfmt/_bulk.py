"""A fast path for large, clean files, read with pyarrow's CSV parser when it is installed.

It only ever answers for files where every pose line is plain ``time,name,number,...``: no
``*``, no empty cell, no blank line, no lone CR, no long line, no nan/inf/marker value, valid
times in strictly increasing order and none beyond the 2**31 - 1 ms a C ``int`` holds (Webots'
time arithmetic wraps there). For such lines pyarrow's parser (correctly rounded, whole-cell)
and glibc's ``sscanf`` read the same doubles; anything else makes this module answer ``None`` and
the reader takes its exact line-by-line path. A test checks that both paths agree.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from motiontool.motionfmt.cscan import INT_MAX

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt
    import pyarrow as pa

__all__ = ["read_clean_body"]


def _times(column: pa.Array, fields: int | None) -> tuple[npt.NDArray[np.int64], int] | None:
    """Times in ms of a column of time tokens (one batch of them) and how many ``:`` fields
    each has, if all are plain and have the same number of fields (``fields``, where a batch
    before said)."""
    import numpy as np
    import pyarrow as pa
    import pyarrow.compute as pc

    try:
        text = column.cast(pa.string())
    except pa.ArrowInvalid:  # not UTF-8, so not a valid time either
        return None
    if not pc.all(pc.match_substring_regex(text, r"^\d{1,5}(:\d{1,5}){0,2}$")).as_py():
        return None
    split = pc.split_pattern(text, ":")
    counts = pc.list_value_length(split).to_numpy()
    k = int(counts[0]) if fields is None else fields
    if not bool((counts == k).all()):
        return None
    parts = pc.cast(pc.list_flatten(split), pa.int64()).to_numpy().reshape(-1, k)
    return parts @ np.array([60000, 1000, 1][-k:], dtype=np.int64), k


def _longest_line(data: bytes, start: int) -> int:
    """The longest line of ``data[start:]`` in bytes, newline excluded; scanned a few MiB at a
    time (no copy of the file)."""
    import numpy as np

    longest, line_start, step = 0, start, 1 << 22
    for chunk in range(start, len(data), step):
        raw = np.frombuffer(data, dtype=np.uint8, count=min(step, len(data) - chunk), offset=chunk)
        ends = np.flatnonzero(raw == 10) + chunk
        if ends.size:
            starts = np.concatenate(([line_start], ends[:-1] + 1))
            longest = max(longest, int((ends - starts).max()))
            line_start = int(ends[-1]) + 1
    return max(longest, len(data) - line_start)


def read_clean_body(
    data: bytes, n_joints: int, marker: float, max_line: int, start: int = 0
) -> tuple[list[int], list[str], npt.NDArray[np.float64]] | None:
    """Times (ms), pose names and values (P, J) of the pose lines in ``data[start:]`` (the file
    after its header line), or ``None``.

    The lines are parsed a block at a time into arrays of their final size: no copy of the
    file, and no table of it all besides them.

    Args:
        data, start: the file, and where its pose lines start.
        n_joints: J, from the header.
        marker: Webots' 'no value' number; a file holding it takes the exact path.
        max_line: the longest line (bytes, newline excluded) that Webots reads in one piece.
    """
    if start >= len(data) or n_joints < 1 or not _plain(data, start):
        return None
    try:
        import numpy as np
        import pyarrow  # noqa: F401 - the fast path needs it; without it, the exact path
    except ImportError:
        return None
    if _longest_line(data, start) > max_line:
        return None
    n_poses = data.count(b"\n", start) + (0 if data.endswith(b"\n") else 1)
    values = np.empty((n_poses, n_joints), dtype=np.float64)
    times = np.empty(n_poses, dtype=np.int64)
    names: list[str] = []
    row, fields = 0, None
    for batch in _batches(memoryview(data)[start:], n_joints):
        k = batch.num_rows
        if (
            batch.num_columns != n_joints + 2
            or row + k > n_poses
            or any(c.null_count for c in batch.columns)
        ):
            return None
        for j in range(n_joints):
            values[row : row + k, j] = batch.column(j + 2).to_numpy()
        got = _times(batch.column(0), fields)
        if got is None:
            return None
        times[row : row + k], fields = got
        names += _names(batch.column(1))
        row += k
    if row != n_poses or not bool(np.isfinite(values).all()) or bool((values == marker).any()):
        return None
    if int(times.max()) > INT_MAX:
        return None  # Webots' int arithmetic wraps: the exact path wraps it too
    if bool((np.diff(times) <= 0).any()):
        return None
    return times.tolist(), names, values


def _names(column: pa.Array) -> list[str]:
    import pyarrow as pa

    try:
        names: list[str] = column.cast(pa.string()).to_pylist()
    except pa.ArrowInvalid:  # not UTF-8: keep the bytes as surrogates
        return [n.decode("utf-8", "surrogateescape") for n in column.to_pylist()]
    return names


def _plain(data: bytes, start: int) -> bool:
    """No byte sequence in ``data[start:]`` that only the exact path reads right: an empty
    cell, a blank line, a lone CR, ``*``, a NUL, ``_`` (Python's ``float`` reads ``1_0``)."""
    for needle in (b",,", b",\n", b",\r", b"\n,", b"\n\n", b"\n\r", b"\r\r", b"*", b"\0", b"_"):
        if data.find(needle, start) >= 0:
            return False
    return not data.startswith((b",", b"\n", b"\r"), start) and data.count(
        b"\r", start
    ) == data.count(b"\r\n", start)


def _batches(body: memoryview, n_joints: int) -> Iterator[pa.RecordBatch]:
    """The pose lines as record batches of columns t, n (bytes) and v0..v{J-1} (float64), a
    block of the file each; stops at a block pyarrow's CSV reader refuses (the caller then
    finds too few rows)."""
    import pyarrow as pa
    import pyarrow.csv as pacsv

    columns = ["t", "n", *(f"v{j}" for j in range(n_joints))]
    types = {"t": pa.binary(), "n": pa.binary(), **{f"v{j}": pa.float64() for j in range(n_joints)}}
    refused = (pa.ArrowInvalid, pa.ArrowTypeError, pa.ArrowNotImplementedError)
    try:
        reader = pacsv.open_csv(
            pa.py_buffer(body),
            read_options=pacsv.ReadOptions(column_names=columns, block_size=_BLOCK),
            parse_options=pacsv.ParseOptions(
                quote_char=False, escape_char=False, ignore_empty_lines=False
            ),
            convert_options=pacsv.ConvertOptions(
                column_types=types,
                null_values=[],
                strings_can_be_null=False,
                quoted_strings_can_be_null=False,
            ),
        )
        yield from reader
    except refused:
        return


_BLOCK = 1 << 20
"""Bytes of the file pyarrow parses at a time."""
