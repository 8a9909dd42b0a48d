"""What ``motiontool info`` tells about a file: shape, timing, undefined cells, line ends."""

from __future__ import annotations

import itertools
import statistics
from dataclasses import dataclass

from motiontool.motionfmt.diagnostics import BLANK_LINE_ENDS, Severity
from motiontool.motionfmt.reader import read_bytes

__all__ = ["MotionSummary", "summarize"]


@dataclass(frozen=True)
class MotionSummary:
    """Facts about one motion file (times in milliseconds).

    Attributes:
        undefined: per joint, the number of ``*`` cells (no command).
        spacing_ms: (min, median, max) time between consecutive poses, or None for one pose.
        line_ends: ``LF``, ``CRLF`` or ``mixed``.
        errors, warnings, notes: the findings of Webots' reading, by severity: what
            ``motiontool validate --robot none`` reports (no robot checks, no time step).
    """

    path: str
    size_bytes: int
    joints: tuple[str, ...]
    poses: int
    first_ms: int
    duration_ms: int
    spacing_ms: tuple[int, float, int] | None
    undefined: dict[str, int]
    line_ends: str
    final_newline: bool
    ignored_after_line: int | None
    errors: int
    warnings: int
    notes: int

    @property
    def uniform(self) -> bool:
        return self.spacing_ms is not None and self.spacing_ms[0] == self.spacing_ms[2]


def summarize(data: bytes, path: str) -> MotionSummary:
    """Summarize a file Webots accepts; raises :class:`MotionSyntaxError` where it stops."""
    read = read_bytes(data, path)
    if not read.accepted:
        read.motion  # raises  # noqa: B018
    times = read.times_ms
    gaps = [b - a for a, b in itertools.pairwise(times)]
    crlf = data.count(b"\r\n")
    lf = data.count(b"\n")
    line_ends = "CRLF" if crlf and crlf == lf else ("mixed" if crlf else "LF")
    undefined = {j: 0 for j in read.joints}
    # '*' and the marker send no command; a 'nan' cell is a command (Webots sends it).
    uncommanded = (~read.motion.commanded).sum(axis=0).tolist()
    for name, count in zip(read.joints, uncommanded, strict=True):
        undefined[name] += int(count)
    return MotionSummary(
        path=path,
        size_bytes=len(data),
        joints=tuple(read.joints),
        poses=len(times),
        first_ms=times[0],
        duration_ms=times[-1],
        spacing_ms=(min(gaps), statistics.median(gaps), max(gaps)) if gaps else None,
        undefined=undefined,
        line_ends=line_ends,
        final_newline=data.endswith(b"\n"),
        ignored_after_line=read.end_line
        if any(d.code == BLANK_LINE_ENDS for d in read.diagnostics)
        else None,
        errors=sum(d.severity is Severity.ERROR for d in read.diagnostics),
        warnings=sum(d.severity is Severity.WARNING for d in read.diagnostics),
        notes=sum(d.severity is Severity.INFO for d in read.diagnostics),
    )
