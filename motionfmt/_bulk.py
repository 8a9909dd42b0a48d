"""A fast path for large, clean files, read with pyarrow's CSV parser when it is installed.

It only ever answers for files where every pose line is plain ``time,name,number,...``: no
``*``, no empty cell, no blank line, no lone CR, no long line, no nan/inf/marker value, valid
times in strictly increasing order and none beyond the 2**31 - 1 ms a C ``int`` holds (Webots'
time arithmetic wraps there). For such lines pyarrow's parser (correctly rounded, whole-cell)
and glibc's ``sscanf`` read the same doubles; anything else makes this module answer ``None`` and
the reader takes its exact line-by-line path. A test checks that both paths agree.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.motionfmt.cscan import INT_MAX

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt
    import pyarrow as pa

__all__ = ["read_clean_body"]


def _times(column: pa.ChunkedArray) -> list[int] | None:
    """Times in ms of a column of time tokens, if all are plain and strictly increasing."""
    import numpy as np
    import pyarrow as pa
    import pyarrow.compute as pc

    try:
        text = column.cast(pa.string())
    except pa.ArrowInvalid:  # not UTF-8, so not a valid time either
        return None
    if not pc.all(pc.match_substring_regex(text, r"^\d{1,5}(:\d{1,5}){0,2}$")).as_py():
        return None
    fields = pc.split_pattern(text, ":")
    counts = pc.list_value_length(fields).to_numpy()
    k = int(counts[0])
    if not bool((counts == k).all()):
        return None
    parts = pc.cast(pc.list_flatten(fields), pa.int64()).to_numpy().reshape(-1, k)
    times = parts @ np.array([60000, 1000, 1][-k:], dtype=np.int64)
    if int(times.max()) > INT_MAX:
        return None  # Webots' int arithmetic wraps: the exact path wraps it too
    if bool((np.diff(times) <= 0).any()):
        return None
    return [int(t) for t in times.tolist()]


def read_clean_body(
    body: bytes, n_joints: int, marker: float, max_line: int
) -> tuple[list[int], list[str], npt.NDArray[np.float64]] | None:
    """Times (ms), pose names and values (P, J) of the pose lines in ``body``, or ``None``.

    Args:
        body: the file after its header line.
        n_joints: J, from the header.
        marker: Webots' 'no value' number; a file holding it takes the exact path.
        max_line: the longest line (bytes, newline excluded) that Webots reads in one piece.
    """
    if not body or n_joints < 1 or not _plain(body):
        return None
    try:
        import numpy as np
        import pyarrow as pa
    except ImportError:
        return None
    raw = np.frombuffer(body, dtype=np.uint8)
    ends = np.flatnonzero(raw == 10)
    starts = np.concatenate(([0], ends + 1))
    stops = np.concatenate((ends, [len(body)]))
    if int((stops - starts).max()) > max_line:
        return None
    table = _table(body, n_joints)
    if (
        table is None
        or table.num_columns != n_joints + 2
        or any(c.null_count for c in table.columns)
    ):
        return None
    values = np.column_stack([table.column(j + 2).to_numpy() for j in range(n_joints)])
    values = np.ascontiguousarray(values, dtype=np.float64)
    if not bool(np.isfinite(values).all()) or bool((values == marker).any()):
        return None
    times = _times(table.column(0))
    if times is None:
        return None
    try:
        names: list[str] = table.column(1).cast(pa.string()).to_pylist()
    except pa.ArrowInvalid:  # not UTF-8: keep the bytes as surrogates
        names = [n.decode("utf-8", "surrogateescape") for n in table.column(1).to_pylist()]
    return times, names, values


def _plain(body: bytes) -> bool:
    """No byte sequence that only the exact path reads right: an empty cell, a blank line, a
    lone CR, ``*``, a NUL, ``_`` (Python's ``float`` reads ``1_0``)."""
    for needle in (b",,", b",\n", b",\r", b"\n,", b"\n\n", b"\n\r", b"\r\r", b"*", b"\0", b"_"):
        if needle in body:
            return False
    return not body.startswith((b",", b"\n", b"\r")) and body.count(b"\r") == body.count(b"\r\n")


def _table(body: bytes, n_joints: int) -> pa.Table | None:
    """The pose lines as columns t, n (bytes) and v0..v{J-1} (float64), or None if pyarrow's CSV
    reader refuses them."""
    import pyarrow as pa
    import pyarrow.csv as pacsv

    columns = ["t", "n", *(f"v{j}" for j in range(n_joints))]
    types = {"t": pa.binary(), "n": pa.binary(), **{f"v{j}": pa.float64() for j in range(n_joints)}}
    try:
        return pacsv.read_csv(
            pa.py_buffer(body),
            read_options=pacsv.ReadOptions(column_names=columns, use_threads=True),
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
    except (pa.ArrowInvalid, pa.ArrowTypeError, pa.ArrowNotImplementedError):
        return None
