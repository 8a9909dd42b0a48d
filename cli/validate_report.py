"""``validate``'s report as it is shown: which robot checked what (the text report's first
line, the JSON report's ``robot`` section), and the report of a run written in its format (or
as ``--statistics``) where it goes, for people or machines."""

from __future__ import annotations

import functools
import itertools
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

from motiontool.cli.color import color_enabled
from motiontool.cli.config import Settings
from motiontool.cli.lint_run import Checked, LintRun
from motiontool.cli.output import emit_stderr, piece_sink, say_wrote
from motiontool.cli.progress import Step
from motiontool.cli.reports import (
    PLAIN,
    REPORTS,
    Context,
    FormatName,
    Order,
    Totals,
    Writer,
    summary,
)
from motiontool.cli.text import plural
from motiontool.extras import install_hint
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.findings import Findings
from motiontool.motionfmt.validate import FileReport, ValidationReport
from motiontool.stamps import stamps

if TYPE_CHECKING:
    from motiontool.kinematics.robot_spec import RobotSpec

__all__ = ["Shown", "Tally", "check_and_report", "render", "render_pieces", "report_pieces"]


def _robots_used(checker: Checked) -> tuple[dict[str, tuple[RobotSpec, list[str]]], list[str]]:
    """{robot name: (spec, files checked against it)}, and the files no robot was found for."""
    used: dict[str, tuple[RobotSpec, list[str]]] = {}
    skipped = []
    for path, spec in checker.used.items():
        if spec is None:
            skipped.append(path)
        else:
            used.setdefault(spec.name, (spec, []))[1].append(path)
    return used, skipped


def _unchecked(report: ValidationReport, checker: Checked) -> tuple[list[str], list[str]]:
    """The files checked at syntax level only, in report order: all of them (Webots rejects
    them, or no robot was found: MT901), and those Webots rejects (no robot check reached them)."""
    skipped = {p for p, spec in checker.used.items() if spec is None}
    paths = report.files.paths
    rejected = [p for p in paths if p not in checker.used]
    every = [p for p in paths if p not in checker.used or p in skipped]
    return every, rejected


def _robot_line(checker: Checked | None, report: ValidationReport) -> str:
    """One line for people: which robot checked what, and how many files Webots rejects (they
    are not checked against a robot)."""
    if checker is None:
        return "robot: none (--robot none): Webots syntax checks only\n"
    rejected = _unchecked(report, checker)[1]
    unchecked = (
        f"not checked against a robot: {plural(len(rejected), 'file')} Webots rejects"
        if rejected
        else ""
    )
    used, skipped = _robots_used(checker)
    parts = []
    for name, (spec, files) in used.items():
        step = checker.timestep_ms or spec.default_timestep_ms
        count = f"{plural(len(files), 'file')}, " if len(used) + bool(skipped) > 1 else ""
        parts.append(
            f"{name} ({count}{step} ms controller step, model sha256 {spec.model_hash[:12]})"
        )
    if skipped:
        parts.append(f"none for {plural(len(skipped), 'file')} (MT901)")
    if not parts:  # no file reached the robot checks (Webots rejects them all)
        return f"robot: {unchecked}\n" if unchecked else ""
    named = []
    for name in checker.checks:
        if name in checker.skipped:
            missing = checker.skipped[name]
            named.append(f"{name} (skipped: {missing.library} is not installed)")
        elif name == "collision":
            named.append(f"{name} (overlaps under {checker.penetration_tolerance_mm:g} mm ignored)")
        else:
            named.append(name)
    checks = ", ".join(named)
    if unchecked:
        checks += f"; {unchecked}"
    return f"robot: {'; '.join(parts)}; checks: {checks}\n"


def _robot_json(
    checker: Checked | None, requested: str, report: ValidationReport
) -> dict[str, Any]:
    """The JSON report's ``robot`` section and the stamps with the model hash."""
    if checker is None:
        return {"stamps": stamps(), "robot": {"requested": requested, "checks": []}}
    used, _skipped = _robots_used(checker)
    robots = [
        {
            "name": name,
            "model_sha256": spec.model_hash,
            "model_file": spec.model_path.name,
            "timestep_ms": checker.timestep_ms or spec.default_timestep_ms,
            "files": files,
        }
        for name, (spec, files) in used.items()
    ]
    only = next(iter(used.values()))[0].model_hash if len(used) == 1 else None
    return {
        "stamps": stamps(only),
        "robot": {
            "requested": requested,
            "checks": list(checker.checks),
            "collision_tolerance_mm": checker.penetration_tolerance_mm,
            "robots": robots,
            "unchecked_files": _unchecked(report, checker)[0],
            "skipped_checks": [
                {
                    "check": name,
                    "library": exc.library,
                    "extra": exc.extra,
                    "install": install_hint(exc.extra),
                }
                for name, exc in checker.skipped.items()
            ],
        },
    }


class Shown(NamedTuple):
    """How the report is shown, as the command line says.

    Attributes:
        format: the report format (``--format``).
        sort: the order of findings (``--sort``).
        statistics: counts per code instead of each finding (``--statistics``).
        quiet: the findings only (``--quiet``).
        output: where it goes (None or ``-``: stdout).
        strict: ``--strict`` / ``--no-strict`` (None: the settings').
        robot: ``--robot`` (None: the settings').
        to_stderr: to stderr, where stdout has standard input's fixed text (``--fix -``).
    """

    format: FormatName
    sort: Order
    statistics: bool = False
    quiet: bool = False
    output: Path | None = None
    strict: bool | None = None
    robot: str | None = None
    to_stderr: bool = False


def check_and_report(run: LintRun, project: Settings, shown: Shown, step: Step) -> None:
    """Check each file of ``run`` and write its report as ``shown``: every file is read and
    checked here, then handed to the report's writer (:func:`report_pieces`), whose pieces
    are written as they come; in color where the format has colors and the terminal takes
    them; ``strict`` and ``robot`` as given, else the ``project``'s settings; the progress
    display (``step``) ends before the first byte written to a terminal."""
    run.report.limit = project.max_findings  # the others are counted, not shown
    output, fmt = shown.output, shown.format.value
    to_stdout = output is None or str(output) == "-"
    color = REPORTS[fmt].colors and color_enabled(sys.stdout, to_file=not to_stdout)
    requested = shown.robot if shown.robot is not None else project.robot
    context = Context(
        color=color,
        order=shown.sort,
        strict=shown.strict if shown.strict is not None else project.strict,
        robot_line=lambda: _robot_line(run.checked, run.report),
        robot_json=lambda: _robot_json(run.checked, requested, run.report),
        quiet=shown.quiet,
    )
    writer = _writer(shown, context)
    if writer.robots_first:
        run.surveyed()  # every file's robot, before the head names them
    tally = Tally(run.report, run.notes)
    if shown.to_stderr:
        step.stop()
        emit_stderr("".join(report_pieces(run.report, writer, tally, run.check)))
        return
    before_writing = step.stop if _to_terminal(output) else None
    with piece_sink(output, color=color, before_writing=before_writing) as write:
        for piece in report_pieces(run.report, writer, tally, run.check):
            write(piece)
    label = "statistics" if shown.statistics else REPORTS[fmt].label
    if not shown.quiet:
        checked = summary(tally.totals()).removeprefix("checked ")
        say_wrote(output, f"{label} report of {checked}")


def _writer(shown: Shown, context: Context) -> Writer:
    """The writer of the report ``shown`` asks for (``--statistics``: counts per code)."""
    if shown.statistics:  # imported where its report is written, as a format's writer is
        from motiontool.cli.reports.statistics import StatisticsJsonWriter, StatisticsWriter

        json = shown.format.value == "json"
        return StatisticsJsonWriter(context) if json else StatisticsWriter(context)
    return REPORTS[shown.format.value].writer(context)


def report_pieces(
    report: ValidationReport,
    writer: Writer,
    tally: Tally,
    check: Callable[[int], FileReport] | None = None,
) -> Iterator[str]:
    """``report`` written by ``writer``, in pieces: each file is checked here (``check(i)``:
    the ``i``-th file read and checked, or its report held from an earlier pass; default
    ``report.files[i]``, for a report the library made), then handed to the writer with the
    findings the report shows of it (the first ``report.limit`` of the run, in file order;
    ``tally`` counts them). A writer never reads or checks a file: an error in a check comes
    from the check, and one file's report is handed over at a time.

    The passes over the files are the writer's: one in file order; with ``order`` severity,
    one to count every file, then one per severity (errors first) over the files that have
    findings of it; a writer that ``counts_first`` is handed every file to count before its
    head, then those with findings shown."""
    files = range(len(report.files))
    checked = report.files.__getitem__ if check is None else check
    if writer.counts_first:
        for i in files:
            f = checked(i)
            writer.count(f, tally.shown(i, f))
            tally.add(i, f)
    yield from writer.head(tally.totals() if writer.counts_first else None)
    if writer.order is Order.file:
        for i in files:
            if writer.counts_first and not tally.limits[i]:
                continue
            f = checked(i)
            yield from writer.file(f, tally.shown(i, f))
            tally.add(i, f)  # counted by the writer's pass over them, unless a limit cut it
    else:
        for i in files:
            tally.add(i, checked(i))  # how many findings of each file are shown
        for severity in sorted(Severity, reverse=True):
            for i in files:
                if tally.counts[i][severity]:
                    f = checked(i)
                    found = tally.shown(i, f)
                    yield from writer.file(f, (d for d in found if d.severity is severity))
    yield from writer.tail(tally.totals())


class Tally:
    """How many findings each file of ``report`` has, by severity, and how many of them a
    report shows (the first ``report.limit`` of the run, in file order), counted as the files
    are handed over in file order (a few ints a file: the reports are not held). Without a
    limit a file is counted once its findings have been written (:meth:`add` after the
    writer's pass: no pass of its own); with one, before (how many are shown). ``notes()``:
    the run's notes, once every file is checked (default: the report's)."""

    def __init__(
        self, report: ValidationReport, notes: Callable[[], list[Diagnostic]] | None = None
    ) -> None:
        self.report = report
        self.notes: Callable[[], list[Diagnostic]] = (
            (lambda: report.notes) if notes is None else notes
        )
        self.left = report.limit
        self.limits: list[int] = []
        self.counts: list[dict[Severity, int]] = []

    def add(self, i: int, f: FileReport) -> None:
        """Count the ``i``-th file, ``f`` (a pass over its findings, unless they are known)."""
        if i < len(self.limits):
            return
        assert i == len(self.limits), "files are counted in file order"
        counts = {s: f.diagnostics.count(s) for s in Severity}
        total = sum(counts.values())
        n = total if self.left is None else min(self.left, total)
        if self.left is not None:
            self.left -= n
        self.limits.append(n)
        self.counts.append(counts)

    def shown(self, i: int, f: FileReport) -> Findings:
        """The findings of the ``i``-th file, ``f``, that the report shows, made as they are
        read (all of them without a limit: their first whole pass counts them)."""
        found = f.diagnostics
        if self.report.limit is None:
            return found
        self.add(i, f)
        return Findings(functools.partial(itertools.islice, found, self.limits[i]))

    def totals(self) -> Totals:
        """The run's totals, once every file is counted."""
        notes = self.notes()
        counts = {
            s: sum(c[s] for c in self.counts) + sum(1 for d in notes if d.severity is s)
            for s in Severity
        }
        found = sum(sum(c.values()) for c in self.counts)
        limit = self.report.limit
        hidden = 0 if limit is None else max(0, found - limit)
        return Totals(len(self.report.files), counts, notes, hidden)


def render_pieces(report: ValidationReport, fmt: str, context: Context = PLAIN) -> Iterator[str]:
    """``report`` rendered as format ``fmt`` (a key of :data:`REPORTS`), in pieces made as
    they are read: a report the library made (:func:`~motiontool.motionfmt.validate_paths`)."""
    try:
        entry = REPORTS[fmt]
    except KeyError:
        raise ValueError(f"unknown format {fmt!r}; choose one of {', '.join(REPORTS)}") from None
    return report_pieces(report, entry.writer(context), Tally(report))


def render(report: ValidationReport, fmt: str, context: Context = PLAIN) -> str:
    """``report`` rendered as format ``fmt`` (a key of :data:`REPORTS`), whole."""
    return "".join(render_pieces(report, fmt, context))


def _to_terminal(output: Path | None) -> bool:
    """Whether the report goes to a terminal (where a progress display must end first)."""
    return (output is None or str(output) == "-") and sys.stdout.isatty()
