"""``--format github``: GitHub Actions workflow commands, one annotation per finding."""

from __future__ import annotations

from collections.abc import Iterator

from motiontool.cli.jsontext import escape_undecodable
from motiontool.cli.reports.common import PLAIN, Context, findings, summary, text_column, with_hint
from motiontool.motionfmt.diagnostics import CODES, Severity
from motiontool.motionfmt.validate import ValidationReport

__all__ = ["render_github"]


def _gh_escape(text: str, *, prop: bool = False) -> str:
    text = text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")
    if prop:
        text = text.replace(":", "%3A").replace(",", "%2C")
    return text


_GH_COMMAND = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def render_github(report: ValidationReport, context: Context = PLAIN) -> Iterator[str]:
    """GitHub Actions workflow commands: one annotation per diagnostic, written as they are
    made, then a summary.

    ``col`` and ``endColumn`` count characters (GitHub's unit), converted from byte columns;
    a run's note (a check skipped for a missing library) is an annotation without a file.
    A name that is not UTF-8 is written as \\xNN, as in the JSON and SARIF reports: the runner
    reads the log as UTF-8.
    """
    for f, d in findings(report, context.order):
        raw = f.source_line(d.line)
        col = text_column(raw, d.column, utf16=False)
        props = [f"file={_gh_escape(d.path, prop=True)}", f"line={d.line}", f"col={col}"]
        if d.end_column and d.end_column >= d.column:
            props.append(f"endColumn={text_column(raw, d.end_column, utf16=False)}")
        title = f"{d.code} {CODES[d.code].title}" if d.code in CODES else d.code
        props.append(f"title={_gh_escape(title, prop=True)}")
        yield _utf8(f"::{_GH_COMMAND[d.severity]} {','.join(props)}::{_gh_escape(with_hint(d))}\n")
    out = []
    for d in report.notes:  # about the run: an annotation without a file
        title = _gh_escape(f"{d.code} {CODES[d.code].title}", prop=True)
        out.append(f"::{_GH_COMMAND[d.severity]} title={title}::{_gh_escape(with_hint(d))}")
    out.append(summary(report))
    yield _utf8("\n".join(out) + "\n")


def _utf8(text: str) -> str:
    clean, _count = escape_undecodable(text)
    return str(clean)
