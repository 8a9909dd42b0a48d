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
import importlib
from collections.abc import Callable
from typing import NamedTuple

from motiontool.cli.reports.common import PLAIN, Context, Order, Totals, Writer, summary

__all__ = [
    "DEFAULT_FORMAT",
    "PLAIN",
    "REPORTS",
    "Context",
    "FormatName",
    "Order",
    "ReportFormat",
    "Totals",
    "Writer",
    "summary",
]


class ReportFormat(NamedTuple):
    """One rendering of a validation report.

    Attributes:
        where: ``module:Class``, the :class:`Writer` class in this package (imported when a
            report is written in this format: a run imports its format's module only).
        help: what it is for, in ``validate --help``.
        colors: whether it may use ANSI colours (on a terminal only).
        label: what a file of it is, in the ``wrote`` line of ``validate -o``.
    """

    where: str
    help: str
    colors: bool = False
    label: str = "text"

    @property
    def writer(self) -> Callable[[Context], Writer]:
        """``writer(context)``: the :class:`Writer` of one report in this format."""
        module, name = self.where.split(":")
        found: Callable[[Context], Writer] = getattr(
            importlib.import_module(f"{__name__}.{module}"), name
        )
        return found


REPORTS: dict[str, ReportFormat] = {
    "text": ReportFormat("text:TextWriter", "for people", colors=True),
    "json": ReportFormat("json_report:JsonWriter", "the versioned JSON report", label="JSON"),
    "sarif": ReportFormat("sarif:SarifWriter", "SARIF 2.1.0 for code scanning", label="SARIF"),
    "github": ReportFormat(
        "github:GithubWriter", "GitHub Actions annotations", label="GitHub annotations"
    ),
    "gitlab": ReportFormat(
        "gitlab:GitlabWriter", "GitLab Code Quality", label="GitLab Code Quality"
    ),
    "junit": ReportFormat(
        "junit:JunitWriter", "JUnit XML, a test case per file", label="JUnit XML"
    ),
}
"""Every report format of ``validate``, by the name ``--format`` takes."""

FormatName = enum.StrEnum(  # type: ignore[misc]
    "FormatName", {name: name for name in REPORTS}, module=__name__
)
"""The choices of ``validate --format``: the keys of :data:`REPORTS`."""

DEFAULT_FORMAT = FormatName("text")
"""``validate``'s report format when none is named: for people."""
