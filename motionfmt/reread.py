"""Read an edited file again from where the edit starts, as ``motiontool server`` does for each
version an editor sends: :class:`Rereader`.

A one-line edit of a 10,000-line motion changes one pose; reading the whole file again costs
tens of milliseconds, re-reading the lines that changed a fraction of one. The reader
(:mod:`.reader`) reads pose lines one after another, and what a line reads as depends on the
lines before it through one thing only: the time and line of the last pose read (a time must
be after the previous one). So a new version whose header and blank lines are as before is
read again from the last pose before the edit, through the changed lines, and on through the
unchanged lines after them until one of them reads as the same pose as before (same time):
from there on every line reads as it did, and its poses and findings are taken from the
previous read (their lines shifted by the lines the edit added or removed). The checks of the
whole motion (:mod:`.motion_checks`) then run on the spliced poses, as a full read runs them.

Anything else is read in full: a changed header, a blank line, a line Webots reads in pieces
(MT111), bytes that are not UTF-8 (MT208), joint names below the header (MT103), no pose
(MT104), and a finding after the edit whose message names a line when the edit adds or removes
lines (its text would change). Either way the result is the one :func:`.reader.read_bytes`
gives (``tests/motionfmt/test_reread.py`` compares them over random edits).
"""

from __future__ import annotations

import bisect
import itertools
from array import array
from typing import TYPE_CHECKING, NamedTuple

from motiontool.motionfmt.diagnostics import BLANK_LINE_ENDS, CUT_LINE
from motiontool.motionfmt.finding_log import FindingLog
from motiontool.motionfmt.header import read_header
from motiontool.motionfmt.lines import FGETS_PIECE, Piece
from motiontool.motionfmt.motion_checks import check_motion
from motiontool.motionfmt.pose_names import PoseNames
from motiontool.motionfmt.read_result import ReadResult
from motiontool.motionfmt.reader import _Reader

if TYPE_CHECKING:
    from collections.abc import Iterator, Sequence

    import numpy as np
    import numpy.typing as npt

__all__ = ["Rereader"]

_READ_IN_FULL = frozenset({CUT_LINE, "MT208", "MT103", "MT104", BLANK_LINE_ENDS})
"""Findings of a read after which the next version is read in full (see the module doc)."""


class _Kept(NamedTuple):
    """A read, with what reading the next version from the edit on needs."""

    result: ReadResult
    n_lines: int  # how many physical lines, as ReadState.lines has them
    final_newline: bool
    body_findings: int | None  # findings before the whole motion's (None: header failed)
    rejecting: Sequence[int]  # where each finding that rejects is among them
    timestep_ms: int | None


class Rereader:
    """Reads the versions of one document, each from the last one (see the module doc).

    Attributes:
        resumed: how many reads went on from the last version (the others were read in full).
    """

    def __init__(self) -> None:
        self._kept: _Kept | None = None
        self.resumed = 0

    def read(
        self, data: bytes, path: str, *, timestep_ms: int | None = None, keep_values: bool = True
    ) -> ReadResult:
        """What :func:`~motiontool.motionfmt.reader.read_bytes` reads of ``data`` (the same
        arguments), from the last version read where it can."""
        if timestep_ms is not None and timestep_ms <= 0:
            raise ValueError(f"timestep_ms must be positive, got {timestep_ms}")
        kept = None if self._kept is None else _resume(self._kept, data, path, timestep_ms)
        if kept is None:
            reader = _Reader(data, path, timestep_ms, keep_values=keep_values)
            result = reader.read()
            kept = _Kept(
                result,
                data.count(b"\n") + (not data.endswith(b"\n")),
                data.endswith(b"\n"),
                reader.body_findings,
                reader.rejecting,
                timestep_ms,
            )
        else:
            self.resumed += 1
        self._kept = kept
        return kept.result


def _lines(data: bytes) -> list[bytes]:
    """The physical lines of ``data`` as :attr:`ReadState.lines` has them."""
    lines = data.split(b"\n")
    if data.endswith(b"\n"):
        lines.pop()
    return lines


def _resume(kept: _Kept, data: bytes, path: str, timestep_ms: int | None) -> _Kept | None:
    """``data`` read from the edit on, after ``kept`` (the last version); None: read it in
    full."""
    old = kept.result
    if (
        kept.body_findings is None
        or path != old.path
        or timestep_ms != kept.timestep_ms
        or not old.joints
        or data.endswith(b"\n") != kept.final_newline
    ):
        return None
    body = old.diagnostics[: kept.body_findings]
    if any(d.code in _READ_IN_FULL for d in body):
        return None
    lines = _lines(data)
    m = len(lines)
    a, b = _unchanged(old.data, data)
    if a == 0 or m < 2 or not all(_plain_line(line) for line in lines[a : m - b]):
        return None
    delta = m - kept.n_lines
    # From the last pose before the edit (the header if none): what the next line reads after.
    k0 = bisect.bisect_left(old.pose_lines, a + 1)
    prev = (old.times_ms[k0 - 1], old.pose_lines[k0 - 1]) if k0 else (-1, 1)

    state = _Reader(data, path, timestep_ms)
    state.lines = lines  # split once
    if not read_header(state, Piece(1, 0, lines[0])):
        return None
    res = state.result
    before, res.rejected_at = len(res.diagnostics), None
    stop = [m]  # the last line read again (1-based): the end, or where it reads as before

    def pieces() -> Iterator[Piece]:
        for i in range(prev[1], m):
            count = len(res.times_ms)
            yield Piece(i + 1, 0, lines[i])
            unchanged = i >= m - b and len(res.times_ms) == count + 1  # read as a pose
            if unchanged and _old_time(old, i + 1 - delta) == res.times_ms[-1]:
                stop[0] = i + 1
                return

    state.read_poses(pieces(), prev)
    if res.end_line is not None:
        return None  # a blank line
    old_stop = stop[0] - delta
    k1 = bisect.bisect_right(old.pose_lines, old_stop)
    # The findings of the lines not read again: those before (the header's first), those after.
    lines_of = [d.line for d in body]
    i0, i1 = bisect.bisect_right(lines_of, prev[1]), bisect.bisect_right(lines_of, old_stop)
    if i1 < len(body) and delta:
        return None  # their messages may name lines
    again = res.diagnostics[before:]
    diagnostics = [*body[:i0], *again, *body[i1:]]
    rejecting = array("q", [i for i in kept.rejecting if i < i0])
    rejecting.extend(i - before + i0 for i in state.rejecting if i >= before)
    rejecting.extend(i - i1 + i0 + len(again) for i in kept.rejecting if i1 <= i < len(body))

    cells, times, names, pose_lines, nan_commands = _spliced(old, (k0, k1), state, delta)
    result = ReadResult(
        path=path,
        diagnostics=FindingLog(diagnostics),
        rejected_at=diagnostics[rejecting[0]] if rejecting else None,
        joints=list(old.joints),
        pose_names=names,
        times_ms=times,
        _cells=cells,
        pose_lines=pose_lines,
        nan_commands=nan_commands,
        _data=data,
    )
    body_findings = len(result.diagnostics)
    if result.accepted:
        import numpy as np

        state.result, state.pose_cols0 = result, array("q")
        # What a full read finds: a '*' (or the no-value marker) among the poses read.
        state.star_seen = int(np.count_nonzero(cells != cells)) > len(nan_commands)
        check_motion(state)
    return _Kept(result, m, kept.final_newline, body_findings, rejecting, timestep_ms)


def _unchanged(old: bytes, new: bytes) -> tuple[int, int]:
    """How many of the first lines and of the last lines of ``new`` are lines of ``old``, byte
    for byte (found with numpy, not line by line; a line or two fewer at most: the line
    around the first and the last byte that differ). ``old`` and ``new`` both end with a
    newline, or neither does; the first lines and the last ones never overlap."""
    import numpy as np

    x, y = np.frombuffer(old, dtype=np.uint8), np.frombuffer(new, dtype=np.uint8)
    k = min(x.shape[0], y.shape[0])
    differ = x[:k] != y[:k]
    first = int(differ.argmax()) if differ.any() else k  # the first byte that differs
    k -= first
    differ = (x[x.shape[0] - k :] != y[y.shape[0] - k :])[::-1]
    same = int(differ.argmax()) if differ.any() else k  # the last bytes alike
    if first == 0:
        return 0, 0
    # The lines that end before the first byte that differs, and those after a newline among
    # the last bytes alike (none after the file's final newline).
    return new.count(b"\n", 0, first), new.count(b"\n", len(new) - same, len(new) - 1)


def _spliced(
    old: ReadResult, kept: tuple[int, int], again: _Reader, delta: int
) -> tuple[
    npt.NDArray[np.float64], array[int], PoseNames, range | array[int], list[tuple[int, int]]
]:
    """The poses of the new version: those of ``old`` before pose ``kept[0]``, those read
    again (``again``'s), those of ``old`` from pose ``kept[1]`` on (their lines shifted by
    ``delta``): (cells, times, names, lines, ``nan`` commands) as :class:`ReadResult` has
    them."""
    import numpy as np

    k0, k1 = kept
    res = again.result
    width = len(old.joints)
    old_cells = np.asarray(old.cells, dtype=np.float64)
    fresh = np.asarray(again.cells, dtype=np.float64)
    cells = np.concatenate([old_cells[: k0 * width], fresh, old_cells[k1 * width :]])
    times = array("q", old.times_ms[:k0])
    times.extend(res.times_ms)
    times.extend(old.times_ms[k1:])
    names = PoseNames(itertools.islice(old.pose_names, k0))
    names.extend(res.pose_names)
    names.extend(list(itertools.islice(old.pose_names, k1, None)))
    lines = np.concatenate(
        [
            _as_array(old.pose_lines[:k0]),
            np.asarray(again.pose_lines, dtype=np.int64),
            _as_array(old.pose_lines[k1:]) + delta,
        ]
    )
    nan_commands = [c for c in old.nan_commands if c[0] < k0]
    nan_commands += [(p + k0, j) for p, j in res.nan_commands]
    shift = k0 + len(res.times_ms) - k1
    nan_commands += [(p + shift, j) for p, j in old.nan_commands if p >= k1]
    return cells, times, names, _pose_lines(lines), nan_commands


def _as_array(lines: Sequence[int]) -> npt.NDArray[np.int64]:
    """Pose lines as an int64 array (a ``range`` without a loop over it)."""
    import numpy as np

    if isinstance(lines, range):
        return np.arange(lines.start, lines.stop, lines.step, dtype=np.int64)
    return np.asarray(lines, dtype=np.int64)


def _plain_line(line: bytes) -> bool:
    """Whether a changed line can be read on its own: one piece for ``fgets`` (no MT111),
    UTF-8 (no MT208)."""
    if len(line) + 1 > FGETS_PIECE:
        return False
    if line.isascii():
        return True
    try:
        line.decode("utf-8")
    except UnicodeDecodeError:
        return False
    return True


def _old_time(old: ReadResult, line: int) -> int | None:
    """The time (ms) of the pose the last version read at ``line``; None: none there."""
    k = bisect.bisect_left(old.pose_lines, line)
    return old.times_ms[k] if k < len(old.pose_lines) and old.pose_lines[k] == line else None


def _pose_lines(at: npt.NDArray[np.int64]) -> range | array[int]:
    """The poses' lines (``at``): a ``range`` where they follow the header one a line (as a
    read in bulk finds them), else an array."""
    if at.size and at[0] == 2 and at[-1] == at.size + 1:  # increasing: one a line
        return range(2, at.size + 2)
    out = array("q")
    out.frombytes(at.tobytes())
    return out
