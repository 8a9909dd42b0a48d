"""Option types shared by several commands."""

from __future__ import annotations

import enum

__all__ = ["ReportFormat", "TableFormat"]


class ReportFormat(enum.StrEnum):
    """Formats of a diagnostics report."""

    text = "text"
    json = "json"
    sarif = "sarif"
    github = "github"


class TableFormat(enum.StrEnum):
    """Formats of a table of numbers."""

    text = "text"
    csv = "csv"
    json = "json"
