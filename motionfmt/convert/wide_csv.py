"""Wide CSV: ``time_ms`` then one column per joint, one row per pose, an empty cell for ``*``.

Written with Python's ``csv`` module, numbers in ``repr`` (the shortest text that reads back
to the same double), so that ``motion -> csv -> motion`` keeps Webots' command stream
bit-identical. Read strictly, every problem one :class:`MotionSyntaxError` at its line and
column: a time that is not whole milliseconds in ``[0, 2147483647]`` or not after the previous
row's, a cell that is not a number (``nan`` and ``inf`` included), a row of the wrong length.
A cell that reads ``*`` is ``*`` too, and so is Webots' -9999999.9 marker, as Webots plays it.
"""

from __future__ import annotations

import csv
import io
import math
import re
from typing import TYPE_CHECKING

from motiontool.errors import MotionSyntaxError
from motiontool.motionfmt.convert.base import Exported, ExportOptions, Imported, ImportOptions
from motiontool.motionfmt.cscan import INT_MAX
from motiontool.motionfmt.nonfinite import refuse_non_finite
from motiontool.motionfmt.reader import NO_VALUE_MARKER
from motiontool.motionfmt.writer import pose_name

if TYPE_CHECKING:
    from motiontool.motionfmt.motion import Motion

__all__ = ["TIME_COLUMN", "read_csv", "write_csv"]

TIME_COLUMN = "time_ms"
"""The first column's name: pose times in whole milliseconds."""

_NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?")
_NON_FINITE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.IGNORECASE)

#: A cell: its text and its 1-based column in the line.
_Cell = tuple[str, int]


def write_csv(motion: Motion, options: ExportOptions) -> Exported:
    """``motion`` as a wide CSV; a ``nan`` or ``inf`` command raises
    :class:`~motiontool.motionfmt.nonfinite.NonFiniteCommandError` (the CSV has no spelling
    for it)."""
    refuse_non_finite(motion)
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow([TIME_COLUMN, *motion.joints])
    for t, row, sent in zip(motion.times_ms, motion.values, motion.commanded, strict=True):
        writer.writerow(
            [str(int(t)), *(repr(float(v)) if c else "" for v, c in zip(row, sent, strict=True))]
        )
    data = out.getvalue().encode("utf-8", "surrogateescape")
    detail = f"{motion.n_joints} joints, times in ms"
    return Exported(data, motion.n_poses, detail)


def split_cells(line: str, path: str, number: int) -> list[_Cell]:
    """The cells of one CSV line (RFC 4180 quoting, ``""`` inside quotes), with their columns."""
    cells: list[_Cell] = []
    i, n = 0, len(line)
    while True:
        start = i
        if i < n and line[i] == '"':
            text: list[str] = []
            i += 1
            while True:
                close = line.find('"', i)
                if close < 0:
                    raise MotionSyntaxError("unterminated quoted cell", path, number, start + 1)
                text.append(line[i:close])
                if line.startswith('""', close):
                    text.append('"')
                    i = close + 2
                    continue
                i = close + 1
                break
            if i < n and line[i] != ",":
                raise MotionSyntaxError("expected ',' after a quoted cell", path, number, i + 1)
            cells.append(("".join(text), start + 1))
        else:
            comma = line.find(",", i)
            i = n if comma < 0 else comma
            cells.append((line[start:i], start + 1))
        if i >= n:
            return cells
        i += 1  # past the comma


def _lines(data: bytes) -> list[str]:
    text = data.decode("utf-8", "surrogateescape").removeprefix("\ufeff")
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()  # the final newline
    return [line.removesuffix("\r") for line in lines]


def _header(line: str, path: str) -> list[_Cell]:
    cells = split_cells(line, path, 1)
    if cells[0][0] != TIME_COLUMN:
        raise MotionSyntaxError(
            f"expected '{TIME_COLUMN}' as the first column, got {cells[0][0]!r}", path, 1, 1
        )
    if len(cells) < 2:
        raise MotionSyntaxError("no joint column after 'time_ms'", path, 1, len(line) + 1)
    for name, col in cells[1:]:
        if not name or any(c in name for c in ",\r\n\0"):
            raise MotionSyntaxError(
                f"joint name {name!r} cannot be a motion's: it must be non-empty, without ',', "
                "CR, LF or NUL",
                path,
                1,
                col,
            )
    return cells[1:]


def _time(cell: _Cell, previous: tuple[int, int] | None, path: str, number: int) -> int:
    text, col = cell
    if not text.isascii() or not text.isdigit():
        raise MotionSyntaxError(
            f"{TIME_COLUMN} must be whole milliseconds (digits only), got {text!r}",
            path,
            number,
            col,
        )
    t = int(text)
    if t > INT_MAX:
        raise MotionSyntaxError(
            f"time {t} ms is beyond {INT_MAX} ms, the longest time Webots reads", path, number, col
        )
    if previous is not None and t <= previous[0]:
        raise MotionSyntaxError(
            f"time {t} ms is not after the previous row's {previous[0]} ms (line {previous[1]}): "
            "times must strictly increase",
            path,
            number,
            col,
        )
    return t


def _value(cell: _Cell, joint: str, path: str, number: int) -> float:
    """The cell's number, or NaN for an empty cell, ``*`` or Webots' no-value marker."""
    text, col = cell
    stripped = text.strip(" \t")
    if stripped in ("", "*"):
        return math.nan
    if _NON_FINITE.fullmatch(stripped):
        raise MotionSyntaxError(
            f"{joint} = {stripped!r} is not a finite number: write a number in rad (m for a "
            "linear joint), or leave the cell empty for no command",
            path,
            number,
            col,
        )
    if not _NUMBER.fullmatch(stripped):
        raise MotionSyntaxError(
            f"expected a number or an empty cell for {joint}, got {text!r}", path, number, col
        )
    value = float(stripped)
    if math.isinf(value):
        raise MotionSyntaxError(
            f"{joint} = {stripped} is too large for a double", path, number, col
        )
    return math.nan if value == NO_VALUE_MARKER else value


def read_csv(data: bytes, path: str, options: ImportOptions | None = None) -> Imported:
    """A wide CSV as a motion (poses named ``Pose<ms>ms``); raises :class:`MotionSyntaxError`
    at the first problem."""
    import numpy as np

    from motiontool.motionfmt.motion import Motion

    lines = _lines(data)
    if not lines:
        raise MotionSyntaxError(f"empty file: expected a header '{TIME_COLUMN},<joint>,...'", path)
    joints = _header(lines[0], path)
    times: list[int] = []
    rows: list[list[float]] = []
    cells: list[list[tuple[int, int]]] = []
    for number, line in enumerate(lines[1:], start=2):
        if not line:
            raise MotionSyntaxError(
                "blank line: every row needs a time and one cell per joint", path, number, 1
            )
        row = split_cells(line, path, number)
        if len(row) != len(joints) + 1:
            col = row[len(joints) + 1][1] if len(row) > len(joints) + 1 else len(line) + 1
            raise MotionSyntaxError(
                f"{len(row)} cells where the header has {len(joints) + 1}", path, number, col
            )
        previous = (times[-1], number - 1) if times else None
        times.append(_time(row[0], previous, path, number))
        rows.append([_value(c, joints[k][0], path, number) for k, c in enumerate(row[1:])])
        cells.append([(number, c[1]) for c in row[1:]])
    if not rows:
        raise MotionSyntaxError("no rows: a motion needs at least one pose", path, 2, 1)
    motion = Motion(
        tuple(name for name, _ in joints),
        tuple(pose_name(t) for t in times),
        np.array(times, dtype=np.int64),
        np.array(rows, dtype=np.float64),
    )
    header = np.array([col for _, col in joints], dtype=np.int64)
    return Imported(motion, path, cells=np.array(cells, dtype=np.int64), header=header)
