"""What one read of a ``.motion`` file found: :class:`ReadResult`."""

from __future__ import annotations

import itertools
from array import array
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from motiontool.errors import MotionSyntaxError
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.finding_log import FindingLog
from motiontool.motionfmt.lines import FGETS_PIECE, plain_cell_spans, token_spans
from motiontool.motionfmt.pose_names import PoseNames

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

    #: (line of a block's first pose, 1-based column and end column of each of its cells).
    _BlockSpans = tuple[int, npt.NDArray[np.int64], npt.NDArray[np.int64]]

__all__ = ["ReadResult"]


_SPAN_CACHE = 256
"""Poses whose token spans :meth:`ReadResult.cell_span` keeps (bounded: a report of millions of
findings reads them in file order, a few poses at a time)."""

_SPAN_BLOCK = 4096
"""Poses whose lines :meth:`ReadResult.cell_spans` tokenises at once."""


@dataclass
class ReadResult:
    """Everything a read found.

    Attributes:
        path: the file as the user named it.
        diagnostics: every finding, as the read made them (in file order but for the checks
            of the whole motion, made last; :meth:`FindingLog.in_order` sorts them), the
            oldest on disk where a file has thousands.
        rejected_at: the error at which Webots' loader stops, or ``None`` when Webots loads the
            file (it may still mis-read it: see the warnings).
        joints: header joint names (undecodable bytes kept as surrogates).
        pose_names, times_ms: the poses Webots reads, in file order (times in ms, as a C int
            array: 8 bytes a pose).
        cells: the poses' values, pose after pose, J a pose (rad, m for linear joints): value
            ``j`` of pose ``p`` is ``cells[p * J + j]`` (:meth:`row`, :attr:`values`); NaN for
            ``*`` and the -9999999.9 marker (no command), and for a literal ``nan`` (a command:
            see ``nan_commands``). A float64 array (``array('d')`` read line by line, a numpy
            array read in bulk): 8 bytes a cell.
        nan_commands: (pose, column) of every cell that holds a literal ``nan``: NaN in
            ``cells``, but a value Webots sends to the motor, unlike ``*``.
        pose_lines: 1-based physical line of each pose (a ``range`` where they follow the
            header one a line, as the bulk read finds them).
        end_line: the blank line that ends the motion early, or ``None``.
    """

    path: str
    diagnostics: FindingLog = field(default_factory=FindingLog)
    rejected_at: Diagnostic | None = None
    joints: list[str] = field(default_factory=list)
    pose_names: PoseNames = field(default_factory=PoseNames)
    times_ms: array[int] = field(default_factory=lambda: array("q"))
    _cells: array[float] | npt.NDArray[np.float64] = field(default_factory=lambda: array("d"))
    pose_lines: Sequence[int] = field(default_factory=list)
    nan_commands: list[tuple[int, int]] = field(default_factory=list)
    end_line: int | None = None
    _motion: Motion | None = field(default=None, repr=False)
    _data: bytes = field(default=b"", repr=False)
    _cols0: Sequence[int] = field(default_factory=list, repr=False)
    _line_starts: list[int] = field(default_factory=list, repr=False)
    _span_cache: dict[int, list[tuple[int, int]]] = field(default_factory=dict, repr=False)
    _block_spans: tuple[tuple[int, int], _BlockSpans | None] | None = field(
        default=None, repr=False, compare=False
    )
    _cells_later: Callable[[], npt.NDArray[np.float64]] | None = field(
        default=None, repr=False, compare=False
    )

    @property
    def cells(self) -> array[float] | npt.NDArray[np.float64]:
        """See the class doc; a read that kept no values (``read_bytes(keep_values=False)``)
        reads them again on first use."""
        if self._cells_later is not None:
            self._cells, self._cells_later = self._cells_later(), None
        return self._cells

    @cells.setter
    def cells(self, cells: array[float] | npt.NDArray[np.float64]) -> None:
        self._cells, self._cells_later = cells, None

    def cells_later(self, read: Callable[[], npt.NDArray[np.float64]]) -> None:
        """Let ``read()`` give :attr:`cells` when they are first asked for (none held until
        then)."""
        self._cells, self._cells_later = array("d"), read

    @property
    def data(self) -> bytes:
        """The bytes that were read."""
        return self._data

    def header_spans(self) -> list[tuple[int, int]]:
        """1-based (column, end column) of each joint name in the header (line 1)."""
        end = self._data.find(b"\n")
        line = self._data[: end if end >= 0 else len(self._data)][:FGETS_PIECE]
        return [(a + 1, b + 1) for a, b in token_spans(line)[2:]]

    def cell_span(self, pose: int, joint: int | None = None) -> tuple[int, int, int]:
        """(line, column, end column), 1-based, of a pose's value cell for column ``joint``
        (0-based), or of its time token when ``joint`` is None — for diagnostics on cells."""
        line = self.pose_lines[pose]
        col0 = self._cols0[pose] if self._cols0 else 0
        spans = self._span_cache.get(pose)
        if spans is None:  # tokenised once per pose, however many diagnostics it gets
            if len(self._span_cache) >= _SPAN_CACHE:  # findings come in file order: the
                self._span_cache.clear()  # poses being reported are the last ones tokenised
            start = self._starts()[line - 1]
            end = self._data.find(b"\n", start)
            content = self._data[start : end if end >= 0 else len(self._data)]
            spans = self._span_cache[pose] = token_spans(content[col0 : col0 + FGETS_PIECE])
        a, b = spans[0 if joint is None else 2 + joint]
        return line, col0 + a + 1, col0 + b + 1

    def _starts(self) -> list[int]:
        """The offset in the file of each physical line's first byte (made on first use)."""
        if not self._line_starts:
            import numpy as np

            newlines = np.flatnonzero(np.frombuffer(self._data, dtype=np.uint8) == ord("\n"))
            self._line_starts = [0, *(newlines + 1).tolist()]
        return self._line_starts

    def cell_spans(
        self, poses: Sequence[int], joints: Sequence[int | None]
    ) -> Iterator[tuple[int, int, int]]:
        """:meth:`cell_span` of each (pose, joint) given, in order: the lines of
        :data:`_SPAN_BLOCK` poses tokenised at once (numpy) where they are plain, the others
        line by line. Fast for many cells in file order (a fix of millions of cells)."""
        import numpy as np

        at = np.asarray(poses, dtype=np.int64).reshape(-1)
        cells = np.array([0 if j is None else 2 + j for j in joints], dtype=np.int64)
        if at.shape != cells.shape:
            raise ValueError(f"{at.shape[0]} poses, {cells.shape[0]} joints")
        if at.shape[0] == 0:
            return
        block = at // _SPAN_BLOCK
        cuts = [0, *(np.flatnonzero(block[1:] != block[:-1]) + 1).tolist(), at.shape[0]]
        for lo, hi in itertools.pairwise(cuts):  # a run of cells in one block of poses
            first = int(block[lo]) * _SPAN_BLOCK
            if self._block_spans is None or self._block_spans[0] != (first, _SPAN_BLOCK):
                # Kept for the next call: a report asks for its findings' cells one at a time.
                self._block_spans = ((first, _SPAN_BLOCK), self._plain_spans(first))
            table = self._block_spans[1]
            if table is None:
                for i in range(lo, hi):
                    yield self.cell_span(int(at[i]), joints[i])
                continue
            line, starts, stops = table
            rows, c = at[lo:hi] - first, cells[lo:hi]
            spans = (line + rows).tolist(), starts[rows, c].tolist(), stops[rows, c].tolist()
            yield from zip(*spans, strict=True)

    def _plain_spans(self, lo: int) -> _BlockSpans | None:
        """(line of pose ``lo``, 1-based column and end column of every cell of poses ``lo``
        to ``lo + _SPAN_BLOCK`` (rows), as :func:`plain_cell_spans` finds them), or None
        where a line is not plain (CR, NUL, cut, an empty cell, a cell too many or few)."""
        import numpy as np

        hi = min(lo + _SPAN_BLOCK, len(self.pose_lines))
        first, last = self.pose_lines[lo], self.pose_lines[hi - 1]
        if last - first != hi - lo - 1 or any(self._cols0[lo:hi]):
            return None
        line_starts = self._starts()
        start = line_starts[first - 1]
        end = line_starts[last] - 1 if last < len(line_starts) else len(self._data)
        if self._data.find(b"\r", start, end) >= 0 or self._data.find(b"\0", start, end) >= 0:
            return None
        text = np.frombuffer(self._data, dtype=np.uint8, count=end - start, offset=start)
        spans = plain_cell_spans(text, hi - lo, 2 + len(self.joints), np.int64)
        if spans is None:
            return None
        starts, stops = spans
        if int((stops[:, -1] - starts[:, 0]).max()) >= FGETS_PIECE:
            return None  # a line Webots reads in pieces
        at = starts[:, :1] - 1  # each line's first byte is column 1
        return first, starts - at, stops - at

    def row(self, pose: int) -> list[float]:
        """The J values of pose ``pose`` (rad, m for linear joints; NaN: see ``cells``)."""
        if not 0 <= pose < len(self.times_ms):
            raise IndexError(f"pose {pose} of {len(self.times_ms)}")
        j = len(self.joints)
        return [float(v) for v in self.cells[pose * j : (pose + 1) * j]]

    @property
    def values(self) -> npt.NDArray[np.float64]:
        """(P, J) float64, read-only: ``cells`` as a table (a view: no copy)."""
        import numpy as np

        table = np.asarray(self.cells, dtype=np.float64).reshape(
            len(self.times_ms), len(self.joints)
        )
        table.flags.writeable = False
        return table

    @property
    def commanded(self) -> npt.NDArray[np.bool_]:
        """(P, J) bool: True where the cell is a command (a number, ``nan`` and ``inf``
        included), False for ``*`` and the -9999999.9 marker."""
        import numpy as np

        mask = ~np.isnan(self.values)
        for p, j in self.nan_commands:
            mask[p, j] = True
        return mask

    @property
    def accepted(self) -> bool:
        """Whether Webots' ``wbu_motion_new`` loads this file."""
        return self.rejected_at is None

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity is Severity.ERROR]

    @property
    def motion(self) -> Motion:
        """The motion Webots plays; raises :class:`MotionSyntaxError` if Webots rejects it."""
        if self.rejected_at is not None:
            d = self.rejected_at
            raise MotionSyntaxError(f"{d.message} [{d.code}]", d.path, d.line, d.column)
        if self._motion is None:
            import numpy as np

            from motiontool.motionfmt.motion import Motion

            # The motion shares the times, values and names (no copy; read-only).
            times = np.asarray(self.times_ms, dtype=np.int64)
            times.flags.writeable = False
            self._motion = Motion(
                joints=tuple(self.joints),
                pose_names=self.pose_names,
                times_ms=times,
                values=self.values,
                commanded=self.commanded,
            )
        return self._motion
