"""Renderings of a validation report, one file each, registered in :data:`REPORTS`.

Adding a format is one new file here (a function ``render(report, context)`` that returns the
text, or yields it in pieces as it goes: a report of millions of findings is then written while
they are made, never held) and one line in :data:`REPORTS`: ``validate --format`` offers every
entry, and the tests render every entry (tests/cli/test_report_formats.py).
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Iterator
from dataclasses import dataclass

from motiontool.cli.reports.common import PLAIN, Context, Order, summary
from motiontool.cli.reports.github import render_github
from motiontool.cli.reports.gitlab import render_gitlab
from motiontool.cli.reports.json_report import JSON_SCHEMA_VERSION, render_json
from motiontool.cli.reports.junit import render_junit
from motiontool.cli.reports.sarif import SARIF_SRCROOT, render_sarif
from motiontool.cli.reports.text import render_text
from motiontool.motionfmt.validate import ValidationReport

__all__ = [
    "DEFAULT_FORMAT",
    "JSON_SCHEMA_VERSION",
    "REPORTS",
    "SARIF_SRCROOT",
    "Context",
    "FormatName",
    "Order",
    "ReportFormat",
    "render",
    "render_pieces",
    "summary",
]


@dataclass(frozen=True)
class ReportFormat:
    """One rendering of a validation report.

    Attributes:
        render: ``(report, context) -> text``, or the text in pieces (an iterator of str, for
            a format that streams its findings: text, json, github).
        help: what it is for, in ``validate --help``.
        colors: whether it may use ANSI colours (on a terminal only).
        label: what a file of it is, in the ``wrote`` line of ``validate -o``.
    """

    render: Callable[[ValidationReport, Context], str | Iterator[str]]
    help: str
    colors: bool = False
    label: str = "text"


REPORTS: dict[str, ReportFormat] = {
    "text": ReportFormat(render_text, "for people", colors=True),
    "json": ReportFormat(render_json, "the versioned JSON report", label="JSON"),
    "sarif": ReportFormat(render_sarif, "SARIF 2.1.0 for code scanning", label="SARIF"),
    "github": ReportFormat(render_github, "GitHub Actions annotations", label="GitHub annotations"),
    "gitlab": ReportFormat(render_gitlab, "GitLab Code Quality", label="GitLab Code Quality"),
    "junit": ReportFormat(render_junit, "JUnit XML, a test case per file", label="JUnit XML"),
}
"""Every report format of ``validate``, by the name ``--format`` takes."""

FormatName = enum.StrEnum(  # type: ignore[misc]
    "FormatName", {name: name for name in REPORTS}, module=__name__
)
"""The choices of ``validate --format``: the keys of :data:`REPORTS`."""

DEFAULT_FORMAT = FormatName("text")
"""``validate``'s report format when none is named: for people."""


def render_pieces(report: ValidationReport, fmt: str, context: Context = PLAIN) -> Iterator[str]:
    """``report`` rendered as format ``fmt`` (a key of :data:`REPORTS`), in pieces made as
    they are read (the whole text at once for a format that does not stream)."""
    try:
        entry = REPORTS[fmt]
    except KeyError:
        raise ValueError(f"unknown format {fmt!r}; choose one of {', '.join(REPORTS)}") from None
    text = entry.render(report, context)
    return iter((text,)) if isinstance(text, str) else text


def render(report: ValidationReport, fmt: str, context: Context = PLAIN) -> str:
    """``report`` rendered as format ``fmt`` (a key of :data:`REPORTS`), whole."""
    return "".join(render_pieces(report, fmt, context))
