"""``validate --statistics``: how many findings of each code, most frequent first (as ruff).

Two counts per code, named in the header: ``findings``, as the report lists them (a grouped
finding counts once), and ``per pose``, what they stand for (a grouped finding counts each of
its poses: ``--no-group``'s findings). ``--statistics --format json`` gives the same rows, with
how many of each code ``--fix`` fixes, as a ``motiontool.statistics`` report (its schema:
``cli/schemas/statistics.schema.json``).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field

from motiontool.cli.reports.common import Context, Order, Totals, Writer, summary
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport
from motiontool.stamps import stamps

__all__ = ["STATISTICS_SCHEMA_VERSION", "StatisticsJsonWriter", "StatisticsWriter"]

STATISTICS_SCHEMA_VERSION = 1

_HEADER = ("findings", "per pose")


@dataclass
class _Counts:
    """Per code: the findings listed, the per-pose findings they stand for, those ``--fix``
    fixes; the codes, most per-pose findings first."""

    listed: Counter[str] = field(default_factory=Counter)
    per_pose: Counter[str] = field(default_factory=Counter)
    fixable: Counter[str] = field(default_factory=Counter)

    def add(self, f: FileReport, shown: Iterable[Diagnostic], *, fixes: bool) -> None:
        for d in shown:
            self.listed[d.code] += 1
            self.per_pose[d.code] += d.count
            if fixes:
                fix = f.fix_summary(d)
                self.fixable[d.code] += fix is not None and fix[0]

    def rows(self) -> list[str]:
        return sorted(self.listed, key=lambda c: (-self.per_pose[c], -self.listed[c], c))


class StatisticsWriter(Writer):
    """A header, then one line per code: its findings, the per-pose findings they stand for,
    the code, its default severity and title (the most per-pose findings first); then the
    summary line. Written once every file is counted."""

    fixes = False

    def __init__(self, context: Context | None = None) -> None:
        super().__init__(context)
        self.order = Order.file
        self.counts = _Counts()

    def file(self, f: FileReport, shown: Iterable[Diagnostic]) -> Iterator[str]:
        self.counts.add(f, shown, fixes=self.fixes)
        return iter(())

    def tail(self, totals: Totals) -> Iterator[str]:
        counts = self.counts
        listed, per_pose, rows = counts.listed, counts.per_pose, counts.rows()
        w1 = max([len(_HEADER[0])] + [len(f"{listed[c]:,}") for c in rows])
        w2 = max([len(_HEADER[1])] + [len(f"{per_pose[c]:,}") for c in rows])
        robot_line = self.context.robot_line()
        lines = [robot_line.rstrip("\n")] if robot_line else []
        lines.append(f"{_HEADER[0]:>{w1}}  {_HEADER[1]:>{w2}}  code   severity  title")
        for code in rows:
            info = CODES.get(code)
            severity, title = (str(info.severity), info.title) if info else ("", "")
            lines.append(
                f"{listed[code]:>{w1},}  {per_pose[code]:>{w2},}  {code}  {severity:<8}  {title}"
            )
        lines.append(summary(totals))
        yield "\n".join(lines) + "\n"


class StatisticsJsonWriter(StatisticsWriter):
    """``--statistics --format json``: a ``motiontool.statistics`` report, one entry a code
    (most per-pose findings first) with its findings, the per-pose findings they stand for and
    how many ``--fix`` fixes, then the summary's counts."""

    fixes = True

    def tail(self, totals: Totals) -> Iterator[str]:
        from motiontool.cli.jsontext import dumps  # json: imported where JSON is written

        rows = []
        for code in self.counts.rows():
            info = CODES.get(code)
            rows.append(
                {
                    "code": code,
                    "severity": str(info.severity) if info else None,
                    "title": info.title if info else None,
                    "findings": self.counts.listed[code],
                    "per_pose": self.counts.per_pose[code],
                    "fixable": self.counts.fixable[code],
                }
            )
        doc = {
            "schema": "motiontool.statistics",
            "schema_version": STATISTICS_SCHEMA_VERSION,
            "stamps": self.context.robot_json().get("stamps") or stamps(),
            "statistics": rows,
            "summary": {
                "files": totals.files,
                "errors": totals.found(Severity.ERROR),
                "warnings": totals.found(Severity.WARNING),
                "notes": totals.found(Severity.INFO),
            },
        }
        yield dumps(doc)
