"""``--format gitlab``: GitLab Code Quality (the ``codequality`` report artifact of a job)."""

from __future__ import annotations

from collections.abc import Iterable, Iterator

from motiontool.cli.jsontext import JsonList, escape_undecodable, indented
from motiontool.cli.reports.common import (
    Context,
    Fingerprints,
    Totals,
    Writer,
    relative_path,
    with_hint,
)
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport

__all__ = ["GitlabWriter"]

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


class GitlabWriter(Writer):
    """A JSON array of Code Quality issues: ``description``, ``check_name`` (the code),
    ``fingerprint``, ``severity`` and ``location`` (``path``, ``lines.begin``; ``lines.end``
    for a grouped finding), written as the findings are made.

    A fingerprint identifies one finding across runs and commits
    (:class:`~motiontool.cli.reports.common.Fingerprints`: not its line). A run's notes (about
    no file) are left out: a Code Quality issue needs a location.
    """

    def __init__(self, context: Context | None = None) -> None:
        super().__init__(context)
        self.issues = JsonList(0)
        self.fingerprint = Fingerprints()

    def file(self, f: FileReport, shown: Iterable[Diagnostic]) -> Iterator[str]:
        for d in shown:
            title = CODES[d.code].title if d.code in CODES else d.code
            issue = {
                "type": "issue",
                "description": f"{d.code} {with_hint(d)}",
                "check_name": d.code,
                "categories": ["Bug Risk" if d.severity is Severity.ERROR else "Style"],
                "content": {"body": title},
                "fingerprint": self.fingerprint(d, self.order),
                "severity": _SEVERITY[d.severity],
                "location": {"path": _path(d.path), "lines": _lines(d)},
            }
            clean, _count = escape_undecodable(issue)  # a name that is not UTF-8: \xNN
            yield self.issues.item(indented(clean))

    def tail(self, totals: Totals) -> Iterator[str]:
        yield self.issues.close()
        yield "\n"
