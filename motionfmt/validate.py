"""Validate many files in one pass: the library behind ``motiontool validate``."""

from __future__ import annotations

import functools
from bisect import bisect_left, bisect_right
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from motiontool.errors import MotionToolError
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Severity
from motiontool.motionfmt.fileio import collect_motion_files, read_file, source_name
from motiontool.motionfmt.fixes import (
    ROBOT_CODES,
    ROBOT_FIX_TITLES,
    SAFE_CODES,
    UNSAFE_CODES,
    Fix,
    RobotPlanner,
    plan_fixes,
)
from motiontool.motionfmt.grouping import group_findings
from motiontool.motionfmt.reader import ReadResult, read_bytes

__all__ = ["Check", "FileReport", "ValidationReport", "validate_bytes", "validate_paths"]

Check = Callable[[ReadResult], list[Diagnostic]]
"""An extra check run on every file Webots accepts (robot limits, velocities, ...)."""


@dataclass
class FileReport:
    """The findings for one file, sorted by position.

    ``robot_fixes``: plans the fixes that need the robot the file was checked against
    (:data:`~motiontool.motionfmt.fixes.ROBOT_CODES`), given by the caller that knows it;
    None: those findings have no fix here.
    """

    path: str
    read: ReadResult
    diagnostics: list[Diagnostic]
    data: bytes = field(default=b"", repr=False)
    robot_fixes: RobotPlanner | None = field(default=None, repr=False, compare=False)

    @functools.cached_property
    def _lines(self) -> list[bytes]:
        return self.data.split(b"\n")

    def source_line(self, line: int) -> bytes:
        """The bytes of physical line ``line`` (1-based), without its end of line."""
        lines = self._lines
        return lines[line - 1].rstrip(b"\r") if 0 < line <= len(lines) else b""

    def count(self, severity: Severity) -> int:
        return sum(1 for d in self.diagnostics if d.severity is severity)

    @functools.cached_property
    def fixes(self) -> dict[tuple[str, int, int], tuple[Fix, ...]]:
        """The fixes for this file's findings (safe and unsafe), by (code, line, column) of
        the finding they fix (:mod:`motiontool.motionfmt.fixes`)."""
        by_place = dict(self._file_fixes)
        if any(d.code in ROBOT_CODES for d in self.diagnostics) and self.robot_fixes:
            by_place.update(self._robot_fixes(self.robot_fixes(self.data)))
        return by_place

    @functools.cached_property
    def _file_fixes(self) -> dict[tuple[str, int, int], tuple[Fix, ...]]:
        """The fixes that need only the file (not the robot): planned without the robot's,
        which a report that only names fixes never has to plan."""
        by_place: dict[tuple[str, int, int], tuple[Fix, ...]] = {}
        if not any(d.code in SAFE_CODES | UNSAFE_CODES for d in self.diagnostics):
            return by_place
        planned = plan_fixes(self.data, self.path, unsafe=True, result=self.read)
        merges = tuple(f for f in planned if f.code == "MT205")
        for f in planned:
            if f.code != "MT205":
                by_place[(f.code, f.line, f.column)] = (f,)
        for d in self.diagnostics:
            if d.code == "MT205" and merges:
                by_place[(d.code, d.line, d.column)] = merges
        return by_place

    def _robot_fixes(self, planned: list[Fix]) -> dict[tuple[str, int, int], tuple[Fix, ...]]:
        """Each robot finding's edits: an MT302 finding's are its joint's clamps on its lines
        (a grouped finding's run of lines); the whole retiming belongs to the file's first MT303
        finding (one retiming fixes every segment, and a report stays linear in size)."""
        stretch = tuple(f for f in planned if f.code == "MT303")
        clamps: dict[str | None, list[Fix]] = {}
        for f in planned:
            if f.code == "MT302":
                clamps.setdefault(f.joint, []).append(f)  # in line order
        lines = {joint: [f.line for f in fixes] for joint, fixes in clamps.items()}
        out: dict[tuple[str, int, int], tuple[Fix, ...]] = {}
        first = self._first_stretch
        if first is not None and stretch:
            out[(first.code, first.line, first.column)] = stretch
        for d in self.diagnostics:
            if d.code == "MT302" and d.joint in clamps:
                last = d.line if d.run is None else d.run.end_line
                at = lines[d.joint]
                mine = clamps[d.joint][bisect_left(at, d.line) : bisect_right(at, last)]
                if mine:
                    out[(d.code, d.line, d.column)] = tuple(mine)
        return out

    def fix_summary(self, d: Diagnostic) -> tuple[bool, str] | None:
        """(safe, what it does) of finding ``d``'s fix, or None: no fix. The robot's fixes are
        not planned for it (a report that only names them stays cheap)."""
        if d.code in ROBOT_CODES:
            if self.robot_fixes is None or (d.code == "MT303" and d is not self._first_stretch):
                return None
            return False, ROBOT_FIX_TITLES[d.code]
        if d.code not in SAFE_CODES | UNSAFE_CODES:
            return None
        fixes = self._file_fixes.get((d.code, d.line, d.column), ())
        return (all(f.safe for f in fixes), fixes[0].title) if fixes else None

    @functools.cached_property
    def _first_stretch(self) -> Diagnostic | None:
        """The first MT303 finding, in file order: it carries the retiming that fixes them all."""
        return next((d for d in self.diagnostics if d.code == "MT303"), None)

    def fix_of(self, d: Diagnostic) -> tuple[Fix, ...]:
        """The edits that fix finding ``d`` (empty: none)."""
        return self.fixes.get((d.code, d.line, d.column), ())


@dataclass
class ValidationReport:
    """The findings for every file of one ``validate`` run, and the run's own notes (about no
    file: a check skipped for a missing library, MT902; ``path`` empty, line and column 0)."""

    files: list[FileReport] = field(default_factory=list)
    notes: list[Diagnostic] = field(default_factory=list)
    hidden: dict[Severity, int] = field(default_factory=dict)
    """Findings left out of ``files`` (a cap on how many are shown), by severity: counted,
    and they fail a run as the shown ones do."""

    def count(self, severity: Severity) -> int:
        shown = sum(f.count(severity) for f in self.files)
        return (
            shown
            + sum(1 for d in self.notes if d.severity is severity)
            + self.hidden.get(severity, 0)
        )

    @property
    def diagnostics(self) -> list[Diagnostic]:
        """Every file's findings, then the run's notes."""
        return [d for f in self.files for d in f.diagnostics] + self.notes

    def failed(self, *, strict: bool = False) -> bool:
        """Errors fail a run; with ``strict``, warnings do too."""
        worst = Severity.WARNING if strict else Severity.ERROR
        if any(n for sev, n in self.hidden.items() if sev >= worst):
            return True
        return any(d.severity >= worst for d in self.diagnostics)


def _check_codes(codes: Iterable[str]) -> frozenset[str]:
    codes = frozenset(c.strip().upper() for c in codes if c.strip())
    unknown = sorted(c for c in codes if c not in CODES and not c.startswith("MT3"))
    if unknown:
        raise MotionToolError(
            f"unknown diagnostic code {', '.join(unknown)}; codes are listed by 'motiontool codes'"
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
) -> FileReport:
    """Validate one file's bytes: Webots' reading, then ``checks`` if Webots accepts the file.

    ``group``: each check's consecutive per-pose findings of one code and subject become one
    finding (:func:`~motiontool.motionfmt.grouping.group_findings`), as each check returns
    them, so that one file's findings are never all held ungrouped besides one check's.
    ``on_step``: told what is being done (``path: read``, ``path: checks``), for a progress
    display."""
    if on_step is not None:
        on_step(f"{path}: read")
    result = read_bytes(data, path, timestep_ms=timestep_ms)
    if on_step is not None and checks:
        on_step(f"{path}: checks")
    diagnostics = list(result.diagnostics)
    if result.accepted and result.times_ms and result.joints:
        for check in checks:
            found = _run_check(check, result, group)
            diagnostics.extend(group_findings(found) if group else found)
    skip = _check_codes(ignore)
    kept = sorted((d for d in diagnostics if d.code not in skip), key=Diagnostic.sort_key)
    return FileReport(path=path, read=result, diagnostics=kept, data=data)


def _run_check(check: Check, result: ReadResult, group: bool) -> list[Diagnostic]:
    """``check``'s findings on ``result``; with ``group``, from its ``grouped`` method where it
    has one (findings it groups itself, from arrays, as :func:`group_findings` would)."""
    grouped: Check | None = getattr(check, "grouped", None) if group else None
    return grouped(result) if grouped is not None else check(result)


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
    :func:`validate_bytes`.

    Raises:
        MotionToolError: a path is missing or unreadable, or a directory has no motion file.
    """
    ignore = _check_codes(ignore)
    report = ValidationReport()
    for p in collect_motion_files(paths):
        data = read_file(p)
        name = source_name(p)
        report.files.append(
            validate_bytes(
                data,
                name,
                timestep_ms=timestep_ms,
                checks=checks,
                ignore=ignore,
                group=group,
                on_step=on_step,
            )
        )
    return report
