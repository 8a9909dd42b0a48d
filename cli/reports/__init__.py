"""Renderings of a validation report, one file each, registered in :data:`REPORTS`.

Adding a format is one new file here (a :class:`~motiontool.cli.reports.common.Writer`: the
text before the files, each file's as it is handed over, the text after them; a report of
millions of findings is then written while they are made, never held) and one line in
:data:`REPORTS`: ``validate --format`` offers every entry, and the tests render every entry
(tests/cli/test_report_formats.py). A writer never reads or checks a file: ``validate``
checks each one and hands it over (:func:`motiontool.cli.validate_report.report_pieces`).

May import the rest of ``cli``, the library layers whose findings it writes and the top-level
modules.
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from dataclasses import dataclass

from motiontool.cli.reports.common import PLAIN, Context, Order, Totals, Writer, summary
from motiontool.cli.reports.github import GithubWriter
from motiontool.cli.reports.gitlab import GitlabWriter
from motiontool.cli.reports.json_report import JSON_SCHEMA_VERSION, JsonWriter
from motiontool.cli.reports.junit import JunitWriter
from motiontool.cli.reports.sarif import SARIF_SRCROOT, SarifWriter
from motiontool.cli.reports.text import TextWriter

__all__ = [
    "DEFAULT_FORMAT",
    "JSON_SCHEMA_VERSION",
    "PLAIN",
    "REPORTS",
    "SARIF_SRCROOT",
    "Context",
    "FormatName",
    "Order",
    "ReportFormat",
    "Totals",
    "Writer",
    "summary",
]


@dataclass(frozen=True)
class ReportFormat:
    """One rendering of a validation report.

    Attributes:
        writer: ``writer(context)``: the :class:`Writer` of one report in this format.
        help: what it is for, in ``validate --help``.
        colors: whether it may use ANSI colours (on a terminal only).
        label: what a file of it is, in the ``wrote`` line of ``validate -o``.
    """

    writer: Callable[[Context], Writer]
    help: str
    colors: bool = False
    label: str = "text"


REPORTS: dict[str, ReportFormat] = {
    "text": ReportFormat(TextWriter, "for people", colors=True),
    "json": ReportFormat(JsonWriter, "the versioned JSON report", label="JSON"),
    "sarif": ReportFormat(SarifWriter, "SARIF 2.1.0 for code scanning", label="SARIF"),
    "github": ReportFormat(GithubWriter, "GitHub Actions annotations", label="GitHub annotations"),
    "gitlab": ReportFormat(GitlabWriter, "GitLab Code Quality", label="GitLab Code Quality"),
    "junit": ReportFormat(JunitWriter, "JUnit XML, a test case per file", label="JUnit XML"),
}
"""Every report format of ``validate``, by the name ``--format`` takes."""

FormatName = enum.StrEnum(  # type: ignore[misc]
    "FormatName", {name: name for name in REPORTS}, module=__name__
)
"""The choices of ``validate --format``: the keys of :data:`REPORTS`."""

DEFAULT_FORMAT = FormatName("text")
"""``validate``'s report format when none is named: for people."""
