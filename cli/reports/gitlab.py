"""``--format gitlab``: GitLab Code Quality (the ``codequality`` report artifact of a job)."""

from __future__ import annotations

from collections.abc import Iterator

from motiontool.cli.jsontext import escape_undecodable, indented, list_pieces
from motiontool.cli.reports.common import (
    PLAIN,
    Context,
    Fingerprints,
    findings,
    relative_path,
    with_hint,
)
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Severity
from motiontool.motionfmt.validate import ValidationReport

__all__ = ["render_gitlab"]

_SEVERITY = {Severity.ERROR: "major", Severity.WARNING: "minor", Severity.INFO: "info"}
"""GitLab's severities are info, minor, major, critical and blocker."""


def _path(path: str) -> str:
    """The file relative to the repository root (GitLab shows paths from it), or as given
    for a file outside it."""
    rel = relative_path(path)
    return path if rel is None else rel.as_posix()


def _lines(d: Diagnostic) -> dict[str, int]:
    """``begin``, and for a grouped finding ``end``: its last pose's line."""
    lines = {"begin": max(d.line, 1)}
    if d.run is not None:
        lines["end"] = d.run.end_line
    return lines


def render_gitlab(report: ValidationReport, context: Context = PLAIN) -> Iterator[str]:
    """A JSON array of Code Quality issues: ``description``, ``check_name`` (the code),
    ``fingerprint``, ``severity`` and ``location`` (``path``, ``lines.begin``; ``lines.end``
    for a grouped finding), written as the findings are made.

    A fingerprint identifies one finding across runs and commits
    (:class:`~motiontool.cli.reports.common.Fingerprints`: not its line). A run's notes (about
    no file) are left out: a Code Quality issue needs a location.
    """
    yield from list_pieces(_issues(report, context), 0)
    yield "\n"


def _issues(report: ValidationReport, context: Context) -> Iterator[str]:
    fingerprint = Fingerprints()
    for _file, d in findings(report, context.order):
        title = CODES[d.code].title if d.code in CODES else d.code
        issue = {
            "type": "issue",
            "description": f"{d.code} {with_hint(d)}",
            "check_name": d.code,
            "categories": ["Bug Risk" if d.severity is Severity.ERROR else "Style"],
            "content": {"body": title},
            "fingerprint": fingerprint(d, context.order),
            "severity": _SEVERITY[d.severity],
            "location": {"path": _path(d.path), "lines": _lines(d)},
        }
        clean, _count = escape_undecodable(issue)  # a name that is not UTF-8: \xNN
        yield indented(clean)
