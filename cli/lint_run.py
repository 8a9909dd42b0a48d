"""One ``validate`` run with the project's configuration: each file with the settings of the
closest configuration file (``cli/config.py``), the command line over them.

Files that share a robot, checks, time step and grouping (``group``: consecutive per-pose
findings as one) share one set of robot checks; findings are then kept or left out per file
(``select``, ``ignore``, ``per-file-ignores``), and ``strict`` applies per file. Each file is
read and checked when the command asks for it (:meth:`LintRun.check`), as its report is
written, not all before it starts.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

from motiontool.cli.config import Resolver, Selection, Settings
from motiontool.cli.gitignore import git_ignored
from motiontool.errors import MissingExtraError
from motiontool.kinematics.builtin_robots import NONE
from motiontool.kinematics.checks.registry import CHECK_REGISTRY, DEFAULT_CHECKS, parse_checks
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, FixKind, Severity
from motiontool.motionfmt.fileio import Inputs, collect_motion_files, is_folder, is_stdin
from motiontool.motionfmt.reader import read_bytes
from motiontool.motionfmt.validate import (
    FileReport,
    FileReports,
    ValidationReport,
    checkable,
    validate_bytes,
)

if TYPE_CHECKING:  # a syntax-level run imports no robot and no check
    from motiontool.kinematics.checks.runner import RobotChecks
    from motiontool.kinematics.robot_spec import RobotSpec
    from motiontool.motionfmt.fixes import RobotPlanner
    from motiontool.motionfmt.reread import Rereader  # the editor's: given by the server

__all__ = [
    "Checked",
    "LintRun",
    "Overrides",
    "collect",
    "lint",
    "lint_document",
    "reported",
    "robot_planner",
]


class Overrides(NamedTuple):
    """What the command line says; None where it says nothing (the configuration decides)."""

    robot: str | None = None
    checks: tuple[str, ...] | None = None
    timestep: int | None = None
    strict: bool | None = None
    ignore: tuple[str, ...] = ()
    collision_tolerance_mm: float | None = None
    group: bool | None = None
    select: tuple[str, ...] | None = None
    extend_select: tuple[str, ...] = ()
    force_exclude: bool | None = None
    respect_gitignore: bool | None = None
    stdin_name: str | None = None

    def named(self, path: Path) -> Path:
        """``path``, or for standard input the name ``--stdin-filename`` gives it (what its
        settings are found by)."""
        return Path(self.stdin_name) if self.stdin_name and is_stdin(path) else path

    @property
    def selection(self) -> Selection:
        """The codes the command line selects and ignores (over the configuration's)."""
        return Selection(self.select, self.extend_select, self.ignore)


@dataclass
class Checked:
    """The robot checks of a whole run, merged over its groups of files (what the text
    report's robot line and the JSON report's robot section show)."""

    checks: tuple[str, ...] = ()
    timestep_ms: int | None = None
    penetration_tolerance_mm: float = 0.0
    used: dict[str, RobotSpec | None] = field(default_factory=dict)
    skipped: dict[str, MissingExtraError] = field(default_factory=dict)
    notes: list[Diagnostic] = field(default_factory=list)

    def add(self, checker: RobotChecks) -> None:
        if not self.checks:
            self.checks = checker.checks
            self.timestep_ms = checker.timestep_ms
            self.penetration_tolerance_mm = checker.penetration_tolerance_mm
        else:
            self.checks += tuple(c for c in checker.checks if c not in self.checks)
        self.used.update(checker.used)
        for name, exc in checker.skipped.items():
            self.skipped.setdefault(name, exc)
        messages = {n.message for n in self.notes}
        self.notes += [n for n in checker.notes if n.message not in messages]


@dataclass
class LintRun:
    """A run's files, each read and checked when the command asks (:meth:`check`), their
    report (the first files' held), the robot checks of its groups of files and the files
    whose warnings fail the run."""

    report: ValidationReport
    checkers: list[RobotChecks]
    strict_files: set[str]
    sources: _Sources
    _surveyed: bool = False

    def check(self, i: int) -> FileReport:
        """The ``i``-th file read and checked with its settings and its group's robot checks
        (its report as held, where it is: see :class:`FileReports`)."""
        files = self.report.files
        held = files.held(i)
        if held is not None:
            return held
        files.let_go()  # before the next is made: one report past the budget at a time
        return files.hold(i, self.sources.make(i))

    @property
    def checked(self) -> Checked | None:
        """The robot checks merged over the files checked so far (None: no file of the run
        is checked against a robot)."""
        if not self.checkers:
            return None
        checked = Checked()
        for checker in self.checkers:
            checked.add(checker)
        return checked

    def surveyed(self) -> Checked | None:
        """:attr:`checked` once every file is known (which robot checks it, or none): what a
        report that starts with the robots used needs. The files whose reports are held are
        checked (and held), and the first one past them too (the report reads it next); the
        others are read for their robot, not checked. Once a run."""
        if not self._surveyed:
            self._surveyed = True
            files, sizes = self.report.files, self.sources.inputs.sizes
            past = False  # from the first file past the held bytes on, the others are read
            for i in range(len(files)):
                if files.known(i) is not None:  # checked, all its findings made
                    continue
                if past:
                    self.sources.survey(i)
                    continue
                past = not files.fits(sizes[i])
                self.check(i)
        return self.checked

    def failed(self) -> bool:
        """An error anywhere, or a warning in a file whose settings are strict (findings past
        ``max-findings`` included)."""
        files = self.report.files
        for i, path in enumerate(files.paths):
            if files.tally(i, Severity.ERROR) or (
                path in self.strict_files and files.tally(i, Severity.WARNING)
            ):
                return True
        return any(d.severity >= Severity.ERROR for d in self.notes())

    def notes(self) -> list[Diagnostic]:
        """The run's notes (about no file: a check skipped for a missing library) that the
        command line's selection reports, from the files checked so far."""
        checked, selection = self.checked, self.sources.overrides.selection
        return (
            [] if checked is None else [n for n in checked.notes if selection.decide(n.code, True)]
        )


def collect(
    paths: Sequence[Path], resolver: Resolver, overrides: Overrides | None = None
) -> list[Path]:
    """The motion files of ``paths``: folders searched, less what their settings exclude,
    what ``.gitignore`` ignores and hidden folders (``respect-gitignore``); a file named on the
    command line is kept, but for ``exclude`` with ``force-exclude`` (``overrides``: the
    command line's, over the settings)."""
    o = overrides or Overrides()
    files: list[Path] = []
    for p in paths:
        if is_stdin(p) or not is_folder(p):  # one that cannot be told: read, it says why
            named = o.named(p)
            s = resolver.for_file(named)
            force = o.force_exclude if o.force_exclude is not None else s.force_exclude
            if is_stdin(p) or not (force and s.excluded(named)):  # stdin: never left out
                files.append(p)
            continue
        respect = _respects(p, resolver, o)
        found = []
        # Hidden folders are not searched (respect-gitignore), and what cannot be read in a
        # folder the search leaves out is no error (an unreadable excluded or ignored folder).
        for f in collect_motion_files(
            [p], skip_hidden=respect, left_out=lambda met: _left_out(met, resolver, o)
        ):
            s = resolver.for_file(f)
            if not s.excluded(f):
                found.append((f, _respects(f, resolver, o)))
        ignored = git_ignored(f for f, respect in found if respect)
        files.extend(f for f, _respect in found if f not in ignored)
    return files


def _respects(path: Path, resolver: Resolver, o: Overrides) -> bool:
    """Whether searches leave out what git ignores and hidden folders for ``path``
    (``respect-gitignore``: the command line's, else its settings')."""
    if o.respect_gitignore is not None:
        return o.respect_gitignore
    return resolver.for_file(path).respect_gitignore


def _left_out(met: list[Path], resolver: Resolver, o: Overrides) -> set[Path]:
    """Of the entries a folder search could not read (``met``), those it leaves out: excluded
    by their settings, or ignored by git where ``respect-gitignore`` holds."""
    excluded = {q for q in met if resolver.for_file(q).excluded(q)}
    return excluded | git_ignored(q for q in met if _respects(q, resolver, o))


_Key = tuple[str, tuple[str, ...] | None, int | None, bool]
"""What files validated together share: robot, checks, time step and grouping."""


def _group_key(f: Path, s: Settings, o: Overrides) -> _Key:
    robot = o.robot if o.robot is not None else s.robot_for(f)
    checks = o.checks if o.checks is not None else s.checks
    timestep = o.timestep if o.timestep is not None else s.timestep
    group = o.group if o.group is not None else s.group
    return robot, checks, timestep, group


def lint(
    files: Sequence[Path],
    resolver: Resolver,
    overrides: Overrides,
    make_checker: Callable[[str, tuple[str, ...] | None, int | None], RobotChecks],
    on_step: Callable[[str], None] | None = None,
    stdin_data: bytes | None = None,
) -> LintRun:
    """The run that validates ``files``, each with its settings and ``overrides`` over them,
    when the command asks for it (:meth:`LintRun.check`; the reports of the first files held,
    :class:`~motiontool.motionfmt.validate.FileReports`: memory stays flat however many files
    there are).

    ``make_checker(robot, checks, timestep)`` builds the robot checks of one group (the CLI
    words its hints); ``checks`` None means the default checks (skipped with a note where a
    library is missing), a tuple means checks asked for by name. Every group's checks are
    built here, so that an unknown robot or check fails before any output. ``on_step`` is
    told what is being done, file by file and check by check (:mod:`motiontool.cli.progress`).
    ``stdin_data``: the bytes to validate for standard input (``--fix -``: its fixed text).
    """
    sources = _Sources(files, resolver, overrides, make_checker, on_step, stdin_data)
    names = sources.names
    reports = FileReports(names, sources.make)
    strict = {
        name
        for name, s in zip(names, sources.settings, strict=True)
        if (overrides.strict if overrides.strict is not None else s.strict)
    }
    checkers = [c for c in sources.checkers.values() if c is not None]
    run = LintRun(ValidationReport(files=reports), checkers, strict, sources)
    run.report.run_notes = run.notes
    return run


class _Sources:
    """The files of one run with their settings and robot checks (those of each group of
    files, built at once): each file validated (:meth:`make`) or only surveyed for its robot
    (:meth:`survey`) when the run asks, read from its
    :class:`~motiontool.motionfmt.fileio.Inputs`."""

    def __init__(
        self,
        files: Sequence[Path],
        resolver: Resolver,
        overrides: Overrides,
        make_checker: Callable[[str, tuple[str, ...] | None, int | None], RobotChecks],
        on_step: Callable[[str], None] | None,
        stdin_data: bytes | None = None,
    ) -> None:
        self.files, self.overrides, self.on_step = files, overrides, on_step
        self.named = [overrides.named(f) for f in files]
        self.settings = [resolver.for_file(f) for f in self.named]
        self.keys = [
            _group_key(f, s, overrides) for f, s in zip(self.named, self.settings, strict=True)
        ]
        self.stdin_data = stdin_data
        self.checkers: dict[_Key, RobotChecks | None] = {}
        for key in self.keys:
            if key not in self.checkers:
                robot, checks, timestep, _grouped = key
                checker = None if robot == NONE else make_checker(robot, checks, timestep)
                if checker is not None:
                    checker.on_check = on_step
                self.checkers[key] = checker
        self.inputs = Inputs(files)
        self.names = [
            str(n) if is_stdin(f) and n != f else name
            for f, n, name in zip(files, self.named, self.inputs.names, strict=True)
        ]

    def read(self, i: int) -> bytes:
        """The bytes of the ``i``-th file (standard input's: ``stdin_data`` where given)."""
        if self.stdin_data is not None and is_stdin(self.files[i]):
            return self.stdin_data
        return self.inputs.read(i)

    def make(self, i: int) -> FileReport:
        """The ``i``-th file read and checked with its settings and its group's robot checks."""
        key = self.keys[i]
        checker, settings, on_step = self.checkers[key], self.settings[i], self.on_step
        data, name, path = self.read(i), self.names[i], self.named[i]
        return _lint_one(data, name, path, settings, checker, key, self.overrides, on_step)[0]

    def survey(self, i: int) -> None:
        """Record the robot that checks the ``i``-th file, reading it without checking it."""
        checker = self.checkers[self.keys[i]]
        if checker is not None:
            name, timestep = self.names[i], self.keys[i][2]
            result = read_bytes(self.read(i), name, timestep_ms=timestep)
            if checkable(result):
                checker.note(result)


def lint_document(
    path: Path,
    data: bytes,
    resolver: Resolver,
    overrides: Overrides,
    make_checker: Callable[[str, tuple[str, ...] | None, int | None], RobotChecks],
    reader: Rereader | None = None,
) -> tuple[FileReport, RobotSpec | None]:
    """``data`` linted as :func:`lint` lints the file at ``path`` (its settings, robot, checks
    and grouping): what an editor shows for the text it holds (``motiontool server``). Also
    the robot it was checked against (None: syntax level only). ``reader``: the document's
    reader, which reads a new version from the edit on (see :mod:`motiontool.motionfmt.reread`)."""
    settings = resolver.for_file(path)
    key = _group_key(path, settings, overrides)
    robot, checks, timestep, _grouped = key
    checker = None if robot == NONE else make_checker(robot, checks, timestep)
    return _lint_one(data, str(path), path, settings, checker, key, overrides, reader=reader)


def _lint_one(
    data: bytes,
    name: str,
    path: Path,
    settings: Settings,
    checker: RobotChecks | None,
    key: _Key,
    overrides: Overrides,
    on_step: Callable[[str], None] | None = None,
    *,
    reader: Rereader | None = None,
) -> tuple[FileReport, RobotSpec | None]:
    """One file's bytes (``data``, reported as ``name``, found at ``path``) read and checked
    as its settings and the command line say: the findings they do not report are left out
    as the library makes them, and the robot's fixes are planned against the robot the file
    was checked with (returned too; None: none), at the step it was checked at."""
    _robot, checks, timestep, grouped = key
    report = validate_bytes(
        data,
        name,
        timestep_ms=timestep,
        checks=[checker] if checker is not None else [],
        ignore=settings.unreported(path, CODES, overrides.selection),
        group=grouped,
        on_step=on_step,
        reader=reader,
    )
    spec = None if checker is None else checker.used.get(report.path)
    report.robot_fixes = _planner(spec, path, settings, checks, overrides, timestep)
    return report, spec


_FIXED_BY_CHECK = {
    code: check.name
    for check in CHECK_REGISTRY
    for code in check.codes
    if CODES[code].fix is FixKind.ROBOT
}
"""The robot fixes, by the check that finds what they fix (a code's fix runs with its check)."""


def _planner(
    spec: RobotSpec | None,
    path: Path,
    settings: Settings,
    checks: tuple[str, ...] | None,
    overrides: Overrides,
    timestep: int | None,
) -> RobotPlanner | None:
    """The robot fixes for ``path`` against ``spec``: those whose finding its settings report
    and whose check runs (None: no robot, or none of them); a stretch keeps pose times on the
    controller's step (``timestep`` ms, else the robot's)."""
    if spec is None:
        return None
    ran = DEFAULT_CHECKS if checks is None else parse_checks(checks)
    cli = overrides.selection
    codes = {
        code
        for code, check in _FIXED_BY_CHECK.items()
        if check in ran and settings.reports(code, path, cli)
    }
    if not codes:
        return None
    from motiontool.kinematics.robot_fixes import planner  # the syntax level plans none

    return planner(spec, str(path), codes, step_ms=timestep or spec.default_timestep_ms)


def reported(path: Path, code: str, resolver: Resolver, overrides: Overrides) -> bool:
    """Whether findings ``code`` in ``path`` are reported: its settings' selection, the
    command line's over it, its ``per-file-ignores`` (what ``--fix`` fixes, too)."""
    path = overrides.named(path)
    return resolver.for_file(path).reports(code, path, overrides.selection)


def robot_planner(
    path: Path, data: bytes, resolver: Resolver, overrides: Overrides
) -> RobotPlanner | None:
    """The robot fixes ``validate --fix --unsafe-fixes`` applies to ``path`` (whose bytes are
    ``data``): against the robot its settings name or the one its joints fit."""
    path = overrides.named(path)
    settings = resolver.for_file(path)
    robot, checks, timestep, _grouped = _group_key(path, settings, overrides)
    if robot == NONE:
        return None
    from motiontool.kinematics.robots import pick_robot

    spec = pick_robot(robot, read_bytes(data, str(path)).joints)
    return _planner(spec, path, settings, checks, overrides, timestep)
