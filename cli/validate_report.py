"""``validate``'s report as it is shown: which robot checked what (the text report's first
line, the JSON report's ``robot`` section), and the report of a run written in its format (or
as ``--statistics``) where it goes, for people or machines."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from motiontool.cli.color import color_enabled
from motiontool.cli.config import Settings
from motiontool.cli.lint_run import Checked, LintRun
from motiontool.cli.output import emit_pieces, emit_stderr, say_wrote
from motiontool.cli.progress import Step
from motiontool.cli.reports import REPORTS, Context, FormatName, Order, render_pieces, summary
from motiontool.cli.reports.statistics import render_statistics, render_statistics_json
from motiontool.cli.text import plural
from motiontool.extras import install_hint
from motiontool.kinematics.robots import RobotSpec
from motiontool.motionfmt.validate import ValidationReport
from motiontool.stamps import stamps

__all__ = ["Shown", "print_report"]


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


@dataclass(frozen=True)
class Shown:
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


def print_report(run: LintRun, project: Settings, shown: Shown, step: Step) -> None:
    """The report of ``run`` as ``shown``, in color where the format has colors and the
    terminal takes them; ``strict`` and ``robot`` as given, else the ``project``'s settings;
    the progress display (``step``) ends before the first byte written to a terminal."""
    run.report.limit = project.max_findings  # the others are counted, not shown
    output, fmt = shown.output, shown.format.value
    to_stdout = output is None or str(output) == "-"
    color = REPORTS[fmt].colors and color_enabled(sys.stdout, to_file=not to_stdout)
    requested = shown.robot if shown.robot is not None else project.robot
    context = Context(
        color=color,
        order=shown.sort,
        strict=shown.strict if shown.strict is not None else project.strict,
        robot_line=lambda: _robot_line(run.surveyed(), run.report),
        robot_json=lambda: _robot_json(run.surveyed(), requested, run.report),
        quiet=shown.quiet,
    )
    report = run.report
    if shown.statistics:
        render = render_statistics_json if fmt == "json" else render_statistics
        pieces = iter((render(report, context),))
    else:
        pieces = render_pieces(report, fmt, context)
    if shown.to_stderr:
        step.stop()
        emit_stderr("".join(pieces))
        return
    before_writing = step.stop if _to_terminal(output) else None
    emit_pieces(pieces, output, color=color, before_writing=before_writing)
    label = "statistics" if shown.statistics else REPORTS[fmt].label
    if not shown.quiet:
        say_wrote(output, f"{label} report of {summary(report).removeprefix('checked ')}")


def _to_terminal(output: Path | None) -> bool:
    """Whether the report goes to a terminal (where a progress display must end first)."""
    return (output is None or str(output) == "-") and sys.stdout.isatty()
