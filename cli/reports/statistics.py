"""``validate --statistics``: how many findings of each code, most frequent first (as ruff).

Two counts per code, named in the header: ``findings``, as the report lists them (a grouped
finding counts once), and ``per pose``, what they stand for (a grouped finding counts each of
its poses: ``--no-group``'s findings). ``--statistics --format json`` gives the same rows, with
how many of each code ``--fix`` fixes, as a ``motiontool.statistics`` report (its schema:
``cli/schemas/statistics.schema.json``).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

from motiontool.cli.jsontext import dumps
from motiontool.cli.reports.common import PLAIN, Context, Order, findings, summary
from motiontool.motionfmt.diagnostics import CODES, Severity
from motiontool.motionfmt.validate import ValidationReport
from motiontool.stamps import stamps

__all__ = ["STATISTICS_SCHEMA_VERSION", "render_statistics", "render_statistics_json"]

STATISTICS_SCHEMA_VERSION = 1

_HEADER = ("findings", "per pose")


@dataclass
class _Counts:
    """Per code: the findings listed, the per-pose findings they stand for, those ``--fix``
    fixes; the codes, most per-pose findings first."""

    listed: Counter[str] = field(default_factory=Counter)
    per_pose: Counter[str] = field(default_factory=Counter)
    fixable: Counter[str] = field(default_factory=Counter)

    @classmethod
    def of(cls, report: ValidationReport, *, fixes: bool = False) -> _Counts:
        counts = cls()
        for f, d in findings(report, Order.file):
            counts.listed[d.code] += 1
            counts.per_pose[d.code] += d.count
            if fixes:
                fix = f.fix_summary(d)
                counts.fixable[d.code] += fix is not None and fix[0]
        return counts

    def rows(self) -> list[str]:
        return sorted(self.listed, key=lambda c: (-self.per_pose[c], -self.listed[c], c))


def render_statistics(report: ValidationReport, context: Context = PLAIN) -> str:
    """A header, then one line per code: its findings, the per-pose findings they stand for,
    the code, its default severity and title (the most per-pose findings first); then the
    summary line."""
    counts = _Counts.of(report)
    listed, per_pose, rows = counts.listed, counts.per_pose, counts.rows()
    w1 = max([len(_HEADER[0])] + [len(f"{listed[c]:,}") for c in rows])
    w2 = max([len(_HEADER[1])] + [len(f"{per_pose[c]:,}") for c in rows])
    robot_line = context.robot_line()
    lines = [robot_line.rstrip("\n")] if robot_line else []
    lines.append(f"{_HEADER[0]:>{w1}}  {_HEADER[1]:>{w2}}  code   severity  title")
    for code in rows:
        info = CODES.get(code)
        severity, title = (str(info.severity), info.title) if info else ("", "")
        lines.append(
            f"{listed[code]:>{w1},}  {per_pose[code]:>{w2},}  {code}  {severity:<8}  {title}"
        )
    lines.append(summary(report))
    return "\n".join(lines) + "\n"


def render_statistics_json(report: ValidationReport, context: Context = PLAIN) -> str:
    """``--statistics --format json``: a ``motiontool.statistics`` report, one entry a code
    (most per-pose findings first) with its findings, the per-pose findings they stand for and
    how many ``--fix`` fixes, then the summary's counts."""
    counts = _Counts.of(report, fixes=True)
    rows = []
    for code in counts.rows():
        info = CODES.get(code)
        rows.append(
            {
                "code": code,
                "severity": str(info.severity) if info else None,
                "title": info.title if info else None,
                "findings": counts.listed[code],
                "per_pose": counts.per_pose[code],
                "fixable": counts.fixable[code],
            }
        )
    doc = {
        "schema": "motiontool.statistics",
        "schema_version": STATISTICS_SCHEMA_VERSION,
        "stamps": context.robot_json().get("stamps") or stamps(),
        "statistics": rows,
        "summary": {
            "files": len(report.files),
            "errors": report.count(Severity.ERROR),
            "warnings": report.count(Severity.WARNING),
            "notes": report.count(Severity.INFO),
        },
    }
    return dumps(doc)
