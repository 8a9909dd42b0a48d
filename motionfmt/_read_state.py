"""What the steps of one read share: the file's lines, what the header said, and the one way to
record a finding (:meth:`ReadState.report`).

The reader (:mod:`.reader`) drives the steps; each step is a function of its own module that
takes this state: the header (:mod:`.header`), a pose line (:mod:`.pose_fast`,
:mod:`.pose_line`), the checks on the whole motion (:mod:`.motion_checks`).
"""

from __future__ import annotations

import functools
from array import array

from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Related, Severity
from motiontool.motionfmt.read_result import ReadResult

__all__ = ["ReadState"]


class ReadState:
    """One pass over one file.

    Attributes:
        data, path: the file's bytes and how diagnostics name it.
        timestep_ms: the controller time step (ms) for MT209 and MT115, or None.
        result: what the read found so far.
        lines: the physical lines, without their ``\\n`` (none after a final newline: ``fgets``
            returns NULL there).
        joint_tokens, n_joints: the header's joint names as bytes, and how many (0 until the
            header is read).
        header_end: 1-based (line, column) just after the header's last token.
        star_seen: a ``*`` (or the no-value marker) was read: the MT207 check has work to do.
        pose_lines: the poses' lines as they are read line by line (``result.pose_lines``).
        pose_cols0: byte offset in its physical line of each pose's piece (0 unless cut;
            empty: 0 for every pose).
        cells: the poses' values as they are read line by line (``result.cells``).
        names_line: the line after a header with no joint, when it holds the joint names
            (MT103 says so there), else None.
        muted, muted_count: a code whose findings follow from another one and are only
            counted (``MT110`` "expected 0 values" after joint names on line 2), and how many.
        rejecting: where in ``result.diagnostics`` each finding that rejects the file is (the
            first is ``result.rejected_at``): what :mod:`.reread` needs to know where Webots
            stops once an edit takes the first one away.
    """

    def __init__(self, data: bytes, path: str, timestep_ms: int | None) -> None:
        self.data = data
        self.path = path
        self.timestep_ms = timestep_ms
        self.pose_lines = array("q")
        self.pose_cols0 = array("q")
        self.cells = array("d")
        self.result = ReadResult(
            path=path,
            _cells=self.cells,
            pose_lines=self.pose_lines,
            _data=data,
            _cols0=self.pose_cols0,
        )
        self.has_final_newline = data.endswith(b"\n")
        self.joint_tokens: list[bytes] = []
        self.n_joints = 0
        self.star_seen = False
        self.header_end = (1, 1)
        self.names_line: int | None = None
        self.muted: str | None = None
        self.muted_count = 0
        self.rejecting = array("q")

    @functools.cached_property
    def lines(self) -> list[bytes]:
        """The physical lines (split when first asked: a large clean file read in bulk never
        is)."""
        lines = self.data.split(b"\n")
        if self.has_final_newline:
            lines.pop()  # fgets returns NULL after the last newline
        return lines

    def report(
        self,
        code: str,
        line: int,
        column: int,
        message: str,
        hint: str | None = None,
        *,
        joint: str | None = None,
        time_ms: int | None = None,
        end_column: int | None = None,
        severity: Severity | None = None,
        rejects: bool | None = None,
        related: tuple[Related, ...] = (),
        stable: str | None = None,
    ) -> None:
        """Record a finding; ``severity`` and ``rejects`` default to the code's (see
        :class:`~motiontool.motionfmt.diagnostics.Code`), the first rejecting one is where
        Webots stops; ``related`` and ``stable`` where the message names other lines (see
        :class:`~motiontool.motionfmt.diagnostics.Diagnostic`)."""
        if code == self.muted:
            self.muted_count += 1
            return
        spec = CODES[code]
        diag = Diagnostic(
            code=code,
            severity=spec.severity if severity is None else severity,
            path=self.path,
            line=line,
            column=column,
            message=message,
            hint=hint,
            joint=joint,
            time_ms=time_ms,
            end_column=end_column,
            related=related,
            stable=stable,
        )
        self.result.diagnostics.append(diag)
        if spec.rejects if rejects is None else rejects:
            self.rejecting.append(len(self.result.diagnostics) - 1)
            if self.result.rejected_at is None:
                self.result.rejected_at = diag
