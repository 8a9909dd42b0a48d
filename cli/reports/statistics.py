"""``validate --statistics``: how many findings of each code, most frequent first (as ruff).

Two counts per code, named in the header: ``findings``, as the report lists them (a grouped
finding counts once), and ``per pose``, what they stand for (a grouped finding counts each of
its poses: ``--no-group``'s findings).
"""

from __future__ import annotations

from collections import Counter

from motiontool.cli.reports.common import PLAIN, Context, Order, findings, summary
from motiontool.motionfmt.diagnostics import CODES
from motiontool.motionfmt.validate import ValidationReport

__all__ = ["render_statistics"]

_HEADER = ("findings", "per pose")


def render_statistics(report: ValidationReport, context: Context = PLAIN) -> str:
    """A header, then one line per code: its findings, the per-pose findings they stand for,
    the code, its default severity and title (the most per-pose findings first); then the
    summary line."""
    listed: Counter[str] = Counter()
    per_pose: Counter[str] = Counter()
    for _f, d in findings(report, Order.file):
        listed[d.code] += 1
        per_pose[d.code] += d.count
    rows = sorted(listed, key=lambda code: (-per_pose[code], -listed[code], code))
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
