"""Validate many files in one pass: the library behind ``motiontool validate``.

A run over many files does not hold them all. A file's report holds its bytes, what the reader
read (float64 values) and the robot checks' tables: about 4 times the file's size at syntax level,
11 times with the robot checks. :class:`FileReports` holds the reports of the first files only,
up to :data:`HELD_INPUT_BYTES` of input; a report past them is let go when the next one is made,
and made again if a report needs it again (the JUnit report counts the findings before it
writes them; ``--sort severity`` reads a file again for each severity it has findings of).
Memory stays flat however many files a run has; what a second pass costs is time.
"""

from __future__ import annotations

import difflib
import functools
import sys
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, overload

from motiontool.errors import MotionToolError
from motiontool.motionfmt.diagnostics import (
    BEYOND_LIMITS,
    CODES,
    JOINT_TWICE,
    TOO_FAST,
    Diagnostic,
    FixKind,
    Severity,
)
from motiontool.motionfmt.fileio import Inputs, collect_motion_files
from motiontool.motionfmt.findings import Findings
from motiontool.motionfmt.grouping import group_findings
from motiontool.motionfmt.reader import ReadResult, read_bytes

if TYPE_CHECKING:  # the fixes are made where a finding's fix is asked for
    from motiontool.motionfmt.fixes import Fix, RobotPlanner
    from motiontool.motionfmt.reread import Rereader  # the editor's reader, given by the server

__all__ = [
    "HELD_INPUT_BYTES",
    "Check",
    "FileReport",
    "FileReports",
    "ValidationReport",
    "check_codes",
    "checkable",
    "run_check",
    "validate_bytes",
    "validate_paths",
]

Check = Callable[[ReadResult], Sequence[Diagnostic]]
"""An extra check run on every file Webots accepts (robot limits, velocities, ...): a list of
findings, or :class:`~motiontool.motionfmt.findings.Findings` made on demand in file order."""


@dataclass
class FileReport:
    """The findings for one file, in file order.

    ``diagnostics`` are :class:`~motiontool.motionfmt.findings.Findings`: made each time they
    are read, never all held (a list given here is held as it is, sorted). ``robot_fixes``:
    plans the fixes that need the robot the file was checked against
    (:data:`~motiontool.motionfmt.fixes.ROBOT_CODES`), given by the caller that knows it;
    None: those findings have no fix here.
    """

    path: str
    read: ReadResult
    diagnostics: Findings
    data: bytes = field(default=b"", repr=False)
    robot_fixes: RobotPlanner | None = field(default=None, repr=False, compare=False)

    def __setattr__(self, name: str, value: object) -> None:
        if name == "diagnostics" and not isinstance(value, Findings):
            value = Findings.of(value)  # type: ignore[arg-type]
        object.__setattr__(self, name, value)

    @functools.cached_property
    def _lines(self) -> list[bytes]:
        return self.data.split(b"\n")

    def source_line(self, line: int) -> bytes:
        """The bytes of physical line ``line`` (1-based), without its end of line."""
        lines = self._lines
        return lines[line - 1].rstrip(b"\r") if 0 < line <= len(lines) else b""

    def count(self, severity: Severity) -> int:
        """How many findings of ``severity`` (counted by the first report that read them all)."""
        return self.diagnostics.count(severity)

    def _reader_fixes(self, d: Diagnostic) -> tuple[Fix, ...]:
        """The fixes of one of the reader's findings, ``d`` (those the file alone gives; made
        for the finding when a report reaches it, never all held): a duplicated joint's are
        the file's merge."""
        if d.code == JOINT_TWICE:
            return self._merges
        from motiontool.motionfmt.fixes import finding_fixes

        return tuple(finding_fixes(d, self.read, self._lines, unsafe=True))

    @functools.cached_property
    def _merges(self) -> tuple[Fix, ...]:
        """The merge of the columns of the joints named twice (MT205): one edit of the file,
        offered only where it is proved to play as before (as ``--fix`` applies it: a merge
        of columns whose ``*`` cells interleave is refused there, and not advertised here)."""
        if not self.read.accepted:
            return ()
        from motiontool.motionfmt.fixes import merge_fixes, proved

        codes = {d.code for d in self.read.diagnostics}
        merges = merge_fixes(self.read, self._lines, codes)
        return tuple(merges) if merges and proved(self.data, merges, self.path) else ()

    @functools.cached_property
    def _stretch(self) -> tuple[Fix, ...]:
        """The retiming that fixes every MT303 finding of this file."""
        assert self.robot_fixes is not None
        return tuple(self.robot_fixes.stretch(self.data, self.read))

    def _robot_fix(self, d: Diagnostic, planner: RobotPlanner) -> tuple[Fix, ...]:
        """An MT302 finding's edits are its joint's clamps on its lines (a grouped finding's
        run of lines), planned for it alone; the whole retiming belongs to the file's first
        MT303 finding (one retiming fixes every segment, and a report stays linear in size)."""
        if d.code == TOO_FAST:
            return self._stretch if self._is_first_stretch(d) else ()
        if d.joint is None:
            return ()
        return tuple(planner.clamps(self.read, d.joint, *self._clamped(d)))

    @staticmethod
    def _clamped(d: Diagnostic) -> tuple[tuple[int, int], float | None]:
        """(first line, last line) and the side of the limits (a value past it, None: either)
        of the cells an MT302 finding's fix clamps: its cell, or its run of lines on one side
        of the limits."""
        if d.run is None:
            return (d.line, d.line), None
        return (d.line, d.run.end_line), d.run.worst.value

    def fix_count(self, d: Diagnostic) -> int:
        """How many edits :meth:`fix_of` gives for finding ``d``; a grouped clamp (thousands
        of cells) is counted without making them."""
        if d.code == BEYOND_LIMITS and self.robot_fixes is not None and d.joint is not None:
            return self.robot_fixes.clamp_count(self.read, d.joint, *self._clamped(d))
        return len(self.fix_of(d))

    def fix_summary(self, d: Diagnostic) -> tuple[bool, str] | None:
        """(safe, what it does) of finding ``d``'s fix, or None: no fix. The robot's fixes are
        not planned for it (a report that only names them stays cheap)."""
        kind = CODES[d.code].fix
        if kind is FixKind.ROBOT:
            if self.robot_fixes is None or (d.code == TOO_FAST and not self._is_first_stretch(d)):
                return None
            return False, self.robot_fixes.titles[d.code]
        if kind is None:
            return None
        fixes = self._reader_fixes(d)
        return (all(f.safe for f in fixes), fixes[0].title) if fixes else None

    @functools.cached_property
    def _first_stretch(self) -> tuple[int, int] | None:
        """(line, column) of the first MT303 finding, in file order: it carries the retiming
        that fixes them all."""
        first = next((d for d in self.diagnostics if d.code == TOO_FAST), None)
        return None if first is None else (first.line, first.column)

    def _is_first_stretch(self, d: Diagnostic) -> bool:
        return d.code == TOO_FAST and (d.line, d.column) == self._first_stretch

    def fix_of(self, d: Diagnostic) -> tuple[Fix, ...]:
        """The edits that fix finding ``d`` (empty: none)."""
        if CODES[d.code].fix is FixKind.ROBOT:
            return () if self.robot_fixes is None else self._robot_fix(d, self.robot_fixes)
        return self._reader_fixes(d)


HELD_INPUT_BYTES = 32 * 2**20
"""How many bytes of input files a run holds the reports of (about 11 times that in memory
with the robot checks); the reports of the files past them are made when read (see the module
doc)."""


class FileReports(Sequence[FileReport]):
    """The files of one run and the reports made of them (see the module doc).

    A report is made by the caller (``validate``'s command checks each file, then holds it:
    :meth:`hold`) or, indexing, by ``make(i)``, which validates the ``i``-th file (named
    ``paths[i]``). The reports of the first files are held while their inputs add up to at most
    ``budget`` bytes (None: :data:`HELD_INPUT_BYTES`); the others are let go when the next is
    made, and their counts by severity are kept once a pass over their findings has made them
    all (a report made again knows them: counting needs no pass, and :meth:`tally` makes none).
    """

    def __init__(
        self,
        paths: Sequence[str],
        make: Callable[[int], FileReport],
        *,
        budget: int | None = None,
    ) -> None:
        self.paths = list(paths)
        self._make = make
        self._budget = HELD_INPUT_BYTES if budget is None else budget
        self._held: dict[int, FileReport] = {}
        self._held_bytes = 0
        self._last: tuple[int, FileReport] | None = None
        self._counts: dict[int, dict[Severity, int]] = {}

    @classmethod
    def of(cls, reports: Iterable[FileReport]) -> FileReports:
        """Reports already made, all held."""
        held = list(reports)
        return cls([r.path for r in held], held.__getitem__, budget=sys.maxsize)

    def __len__(self) -> int:
        return len(self.paths)

    @overload
    def __getitem__(self, index: int) -> FileReport: ...
    @overload
    def __getitem__(self, index: slice) -> list[FileReport]: ...
    def __getitem__(self, index: int | slice) -> FileReport | list[FileReport]:
        if isinstance(index, slice):
            return [self[i] for i in range(len(self))[index]]
        i = range(len(self))[index]  # IndexError past either end
        held = self.held(i)
        if held is not None:
            return held
        self.let_go()
        return self.hold(i, self._make(i))

    def held(self, i: int) -> FileReport | None:
        """The ``i``-th file's report where it is held (or is the last one made), else None."""
        held = self._held.get(i)
        if held is not None:
            return held
        if self._last is not None and self._last[0] == i:
            return self._last[1]
        return None

    def hold(self, i: int, report: FileReport) -> FileReport:
        """Keep ``report``, the ``i``-th file's, just made (by the caller after
        :meth:`let_go`, or by ``make``): held while the budget lasts, else until the next one
        is made; returned."""
        if i in self._counts:
            report.diagnostics.know(self._counts[i])
        size = len(report.data)
        if self.fits(size):
            self._held[i] = report
            self._held_bytes += size
        else:
            self._last = (i, report)
        return report

    def fits(self, size: int) -> bool:
        """Whether a report of a file of ``size`` bytes would be held (within the budget)."""
        return self._held_bytes + size <= self._budget

    def __iter__(self) -> Iterator[FileReport]:
        for i in range(len(self)):
            yield self[i]

    def let_go(self) -> None:
        """Drop the last report made past the budget, keeping its counts if they are known
        (before the next one is made: two are never held past the budget)."""
        if self._last is not None:
            i, report = self._last
            counts = report.diagnostics.counts
            if counts is not None:
                self._counts[i] = counts
            self._last = None

    def known(self, i: int) -> dict[Severity, int] | None:
        """The ``i``-th file's counts by severity, where a whole pass made them (else None)."""
        if i in self._counts:
            return self._counts[i]
        report = self._held.get(i)
        if report is None and self._last is not None and self._last[0] == i:
            report = self._last[1]
        return None if report is None else report.diagnostics.counts

    def tally(self, i: int, severity: Severity) -> int:
        """How many findings of ``severity`` the ``i``-th file has (validated, and a pass over
        its findings, only where they were never counted)."""
        counts = self.known(i)
        if counts is None:
            return self[i].count(severity)
        return counts[severity]

    def total(self, i: int) -> int:
        """How many findings the ``i``-th file has."""
        return sum(self.tally(i, s) for s in Severity)


def _no_notes() -> list[Diagnostic]:
    return []


@dataclass
class ValidationReport:
    """The findings for every file of one ``validate`` run (:class:`FileReports`: a list given
    is held as it is), and the run's own notes (about no file: a check skipped for a missing
    library, MT902; ``path`` empty, line and column 0), from ``run_notes``: they are known once
    the files they are about are validated."""

    files: FileReports = field(default_factory=lambda: FileReports.of([]))
    run_notes: Callable[[], list[Diagnostic]] = field(default=_no_notes, repr=False)
    limit: int | None = None
    """How many findings a report shows at most (``max-findings``; None: all), the first ones
    in file order. Those past it are counted, and they fail a run as the shown ones do."""

    def __setattr__(self, name: str, value: object) -> None:
        if name == "files" and not isinstance(value, FileReports):
            value = FileReports.of(value)  # type: ignore[arg-type]
        object.__setattr__(self, name, value)

    @property
    def notes(self) -> list[Diagnostic]:
        """The run's notes (those of the files validated so far)."""
        return self.run_notes()

    def count(self, severity: Severity) -> int:
        """Every finding of ``severity``, shown or not (past :attr:`limit`), and the notes."""
        files = self.files
        return sum(files.tally(i, severity) for i in range(len(files))) + sum(
            1 for d in self.notes if d.severity is severity
        )

    @property
    def hidden(self) -> int:
        """How many findings :attr:`limit` leaves out of the report."""
        total = sum(self.files.total(i) for i in range(len(self.files)))
        return 0 if self.limit is None else max(0, total - self.limit)

    @property
    def diagnostics(self) -> list[Diagnostic]:
        """Every file's findings, then the run's notes."""
        return [d for f in self.files for d in f.diagnostics] + self.notes

    def failed(self, *, strict: bool = False) -> bool:
        """Errors fail a run; with ``strict``, warnings do too."""
        worst = Severity.WARNING if strict else Severity.ERROR
        return any(self.count(sev) for sev in Severity if sev >= worst)


def check_codes(codes: Iterable[str]) -> frozenset[str]:
    """The codes of ``codes`` (stripped, upper case), each a key of :data:`CODES`, or an error
    naming the first one that is not, with the closest code."""
    codes = frozenset(c.strip().upper() for c in codes if c.strip())
    for code in sorted(c for c in codes if c not in CODES):
        close = difflib.get_close_matches(code, list(CODES), n=1)
        hint = f"did you mean '{close[0]}'? " if close else ""
        raise MotionToolError(
            f"unknown diagnostic code '{code}'; {hint}codes are listed by 'motiontool codes'"
        )
    return codes


def validate_bytes(
    data: bytes,
    path: str,
    *,
    timestep_ms: int | None = None,
    checks: Sequence[Check] = (),
    ignore: Iterable[str] = (),
    group: bool = False,
    on_step: Callable[[str], None] | None = None,
    reader: Rereader | None = None,
) -> FileReport:
    """Validate one file's bytes: Webots' reading, then ``checks`` if Webots accepts the file.

    ``group``: each check's consecutive per-pose findings of one code and subject become one
    finding (:func:`~motiontool.motionfmt.grouping.group_findings`), as each check returns
    them, so that one file's findings are never all held ungrouped besides one check's.
    ``on_step``: told what is being done (``path: read``, ``path: checks``), for a progress
    display. ``reader``: reads ``data`` from the last version it read (an editor's document,
    :class:`~motiontool.motionfmt.reread.Rereader`), where given."""
    if on_step is not None:
        on_step(f"{path}: read")
    read = read_bytes if reader is None else reader.read
    result = read(data, path, timestep_ms=timestep_ms, keep_values=bool(checks))
    if on_step is not None and checks:
        on_step(f"{path}: checks")
    parts: list[Sequence[Diagnostic]] = [result.diagnostics]
    if checkable(result):
        parts.extend(run_check(check, result, group) for check in checks)
    skip = check_codes(ignore)
    found = Findings.merge(parts)
    kept = found.where(lambda d: d.code not in skip) if skip else found
    return FileReport(path=path, read=result, diagnostics=kept, data=data)


def checkable(result: ReadResult) -> bool:
    """Whether the robot checks (``validate_bytes``' ``checks``) run on ``result``: Webots
    accepts the file, and it has poses and joints."""
    return bool(result.accepted and result.times_ms and result.joints)


def run_check(check: Check, result: ReadResult, group: bool) -> Sequence[Diagnostic]:
    """``check``'s findings on ``result``; with ``group``, from its ``grouped`` method where it
    has one (findings it groups itself, from arrays, as :func:`group_findings` would), else
    grouped here."""
    grouped: Check | None = getattr(check, "grouped", None) if group else None
    if grouped is not None:
        return grouped(result)
    found = check(result)
    return group_findings(found) if group else found


def validate_paths(
    paths: Sequence[str | Path],
    *,
    timestep_ms: int | None = None,
    checks: Sequence[Check] = (),
    ignore: Iterable[str] = (),
    group: bool = False,
    on_step: Callable[[str], None] | None = None,
) -> ValidationReport:
    """Validate files and directories (every ``*.motion`` below a directory, recursively);
    ``-`` reads standard input, named ``<stdin>``; ``group``, ``on_step``: see
    :func:`validate_bytes`. Each file is validated when the report's :class:`FileReports`
    is read (``checks`` see a file then, not before).

    Raises:
        MotionToolError: a path is missing or unreadable, or a directory has no motion file.
    """
    ignore = check_codes(ignore)
    inputs = Inputs(collect_motion_files(paths))

    def make(i: int) -> FileReport:
        return validate_bytes(
            inputs.read(i),
            inputs.names[i],
            timestep_ms=timestep_ms,
            checks=checks,
            ignore=ignore,
            group=group,
            on_step=on_step,
        )

    return ValidationReport(files=FileReports(inputs.names, make))
