"""A fast path for large, clean files, read with pyarrow's CSV parser when it is installed.

It only ever answers for files where every pose line is plain ``time,name,number,...``: no
``*``, no empty cell, no blank line, no lone CR, no long line, no nan/inf/marker value, valid
times in strictly increasing order and none beyond the 2**31 - 1 ms a C ``int`` holds (Webots'
time arithmetic wraps there). For such lines pyarrow's parser (correctly rounded, whole-cell)
and glibc's ``sscanf`` read the same doubles; anything else makes this module answer ``None`` and
the reader takes its exact line-by-line path. A test checks that both paths agree.

Only ``pyarrow`` and ``pyarrow.csv`` are imported (``pyarrow.compute`` costs more to import
than this path spends reading): times and names are read from the columns' buffers with numpy.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Iterator
from typing import TYPE_CHECKING

from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.pose_names import PoseNames

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt
    import pyarrow as pa

__all__ = ["read_clean_body"]


def _tokens(column: pa.Array) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.uint8]]:
    """The offsets (n + 1, into the bytes) and the bytes of a column of n binary or string
    tokens, read from its buffers (no copy)."""
    import numpy as np

    _validity, offsets_buf, data_buf = column.buffers()
    offsets = np.frombuffer(
        offsets_buf, dtype=np.int32, count=len(column) + 1, offset=4 * column.offset
    )
    raw = np.frombuffer(data_buf, dtype=np.uint8) if data_buf is not None else np.zeros(0, np.uint8)
    return offsets.astype(np.int64), raw


def _times(column: pa.Array, fields: int | None) -> tuple[npt.NDArray[np.int64], int] | None:
    """Times in ms of a column of time tokens (one batch of them) and how many ``:`` each has,
    if every token is plain (1 to 5 digits, up to twice ``:`` and 1 to 5 digits) and all have
    the same number of ``:`` (``fields``, where a batch before said)."""
    import numpy as np

    offsets, raw = _tokens(column)
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
    return per_field @ np.array([60000, 1000, 1][-(k + 1) :], dtype=np.int64), k


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
) -> tuple[npt.NDArray[np.int64], PoseNames, npt.NDArray[np.float64]] | None:
    """Times (ms), pose names and values (P, J) of the pose lines in ``data[start:]`` (the file
    after its header line), or ``None``.

    The lines are parsed a block at a time into arrays of their final size: no copy of the
    file, and no table of it all besides them. A large file is cut into parts (:func:`_parts`)
    parsed at once, one thread each (pyarrow parses without Python's lock).

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
    parts = _parts(data, start)
    n_poses = sum(rows for _, rows in parts)
    values = np.empty((n_poses, n_joints), dtype=np.float64)
    times = np.empty(n_poses, dtype=np.int64)
    jobs, row = [], 0
    for body, rows in parts:
        jobs.append((body, values[row : row + rows], times[row : row + rows]))
        row += rows
    if len(jobs) == 1:
        got = [_fill(*jobs[0])]
    else:  # pyarrow parses without the GIL: one thread a part
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(len(jobs)) as pool:
            got = list(pool.map(lambda job: _fill(*job), jobs))
    read = [g for g in got if g is not None]
    if len(read) < len(got) or len({f for _, f in read if f is not None}) > 1:
        return None  # a part refused, or parts that write their times differently
    if not bool(np.isfinite(values).all()) or bool((values == marker).any()):
        return None
    if int(times.max()) > INT_MAX:
        return None  # Webots' int arithmetic wraps: the exact path wraps it too
    if bool((np.diff(times) <= 0).any()):
        return None
    names = read[0][0]
    for more, _ in read[1:]:
        names.extend(more)
    return times, names, values


def _parts(data: bytes, start: int) -> list[tuple[memoryview, int]]:
    """``data[start:]`` cut after a newline into as many parts as there are cores (at most
    :data:`_PARTS`; one for a file under :data:`_PART_MIN` bytes), each with its number of
    lines."""
    count = min(_PARTS, os.cpu_count() or 1, max(1, (len(data) - start) // _PART_MIN))
    cuts = [start]
    for i in range(1, count):
        at = data.find(b"\n", start + (len(data) - start) * i // count)
        if at < 0 or at + 1 <= cuts[-1] or at + 1 >= len(data):
            break
        cuts.append(at + 1)
    cuts.append(len(data))
    view = memoryview(data)
    parts = [(view[a:b], data.count(b"\n", a, b)) for a, b in itertools.pairwise(cuts)]
    if not data.endswith(b"\n"):  # the last line has no newline
        parts[-1] = (parts[-1][0], parts[-1][1] + 1)
    return parts


def _fill(
    body: memoryview, values: npt.NDArray[np.float64], times: npt.NDArray[np.int64]
) -> tuple[PoseNames, int | None] | None:
    """Parse the lines of ``body`` into ``values`` and ``times`` (exactly as many rows as it
    has lines); its pose names, and how many ``:`` its times have. None: refused."""
    n_rows, n_joints = values.shape
    names = PoseNames()
    row, fields = 0, None
    for batch in _batches(body, n_joints):
        k = batch.num_rows
        if (
            batch.num_columns != n_joints + 2
            or row + k > n_rows
            or any(c.null_count for c in batch.columns)
        ):
            return None
        for j in range(n_joints):
            values[row : row + k, j] = batch.column(j + 2).to_numpy()
        got = _times(batch.column(0), fields)
        if got is None:
            return None
        times[row : row + k], fields = got
        batch_names = _names(batch.column(1))
        if batch_names is None:
            return None
        names.extend(batch_names)
        row += k
    return (names, fields) if row == n_rows else None


def _names(column: pa.Array) -> list[str] | None:
    """The pose names of a column of them, or None if one is empty (Webots reads the next
    cell as the name: the exact path reports it)."""
    import numpy as np

    offsets, _raw = _tokens(column)
    if len(column) and int(np.diff(offsets).min()) == 0:
        return None
    names: list[str] = column.to_pylist()
    return names


def _plain(data: bytes, start: int) -> bool:
    """No byte in ``data[start:]`` that only the exact path reads right: ``*``, a NUL (it ends
    a C string), ``_`` (Python's ``float`` reads ``1_0``); one ``memchr`` pass each. The rest
    needs no scan of the file: pyarrow refuses an empty cell or a blank line (a column too many
    or too few, an empty number), the time's pattern an empty time, :func:`_names` an empty
    name, and a lone CR ends pyarrow's row where Webots' line goes on, so pyarrow finds more
    rows than the file has lines (:func:`read_clean_body` counts them)."""
    return all(data.find(byte, start) < 0 for byte in (b"*", b"\0", b"_"))


def _batches(body: memoryview, n_joints: int) -> Iterator[pa.RecordBatch]:
    """The pose lines as record batches of columns t, n (bytes) and v0..v{J-1} (float64), a
    block of the file each; stops at a block pyarrow's CSV reader refuses (the caller then
    finds too few rows)."""
    import pyarrow as pa
    import pyarrow.csv as pacsv

    columns = ["t", "n", *(f"v{j}" for j in range(n_joints))]
    # The names as UTF-8 text: a name that is not makes pyarrow refuse the block (exact path).
    types = {"t": pa.binary(), "n": pa.string(), **{f"v{j}": pa.float64() for j in range(n_joints)}}
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
            # The C library's allocator gives each block back: pyarrow's default pool keeps a
            # heap per thread (about 20 MiB more where two parts are read at once).
            memory_pool=pa.system_memory_pool(),
        )
        yield from reader
    except refused:
        return


_BLOCK = 1 << 20
"""Bytes of the file pyarrow parses at a time."""

_PARTS = 2
"""At most this many parts of a file are parsed at once, one thread each."""

_PART_MIN = 4 << 20
"""A part is at least this many bytes (4 blocks): a smaller file is one part."""
