"""``validate --statistics``: how many findings of each code, most frequent first (as ruff)."""

from __future__ import annotations

from collections import Counter

from motiontool.cli.reports.common import PLAIN, Context, summary
from motiontool.motionfmt.diagnostics import CODES
from motiontool.motionfmt.validate import ValidationReport

__all__ = ["render_statistics"]


def render_statistics(report: ValidationReport, context: Context = PLAIN) -> str:
    """One line per code: count, code, default severity and title; then the summary line."""
    counts = Counter(d.code for d in report.diagnostics)
    rows = sorted(counts.items(), key=lambda item: (-item[1], item[0]))
    width = max((len(str(n)) for _code, n in rows), default=1)
    lines = [context.robot_line.rstrip("\n")] if context.robot_line else []
    for code, n in rows:
        info = CODES.get(code)
        severity, title = (str(info.severity), info.title) if info else ("", "")
        lines.append(f"{n:>{width}}  {code}  {severity:<7}  {title}")
    lines.append(summary(report))
    return "\n".join(lines) + "\n"
