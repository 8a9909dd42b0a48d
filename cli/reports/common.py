"""What every rendering of a validation report shares: the order of findings, the summary
line, columns in characters or UTF-16 units, and the context a renderer gets."""

from __future__ import annotations

import enum
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

from motiontool.cli.text import plural
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport, ValidationReport

__all__ = ["PLAIN", "Context", "Order", "findings", "summary", "text_column", "with_hint"]


class Order(enum.StrEnum):
    """Order of the findings in the text, GitHub and SARIF reports."""

    file = "file"  # file by file, by position in each
    severity = "severity"  # errors first, then warnings, then notes (each in file order)


def summary(report: ValidationReport) -> str:
    """``checked 3 files: 1 error, 2 warnings, 0 notes``, then every check skipped for a
    missing library (MT902): ``; collision check skipped: pip install 'motiontool[kinematics]'``."""
    skipped = "".join(
        f"; {d.message.partition(':')[0]}: {d.hint}" for d in report.notes if d.code == "MT902"
    )
    return (
        f"checked {plural(len(report.files), 'file')}: "
        f"{plural(report.count(Severity.ERROR), 'error')}, "
        f"{plural(report.count(Severity.WARNING), 'warning')}, "
        f"{plural(report.count(Severity.INFO), 'note')}{skipped}"
    )


def findings(report: ValidationReport, order: Order) -> Iterator[tuple[FileReport, Diagnostic]]:
    pairs = [(f, d) for f in report.files for d in f.diagnostics]
    if order is Order.severity:
        pairs.sort(key=lambda fd: -fd[1].severity)  # stable: file order within a severity
    return iter(pairs)


def with_hint(d: Diagnostic) -> str:
    """The message, then ``(hint: ...)`` where the diagnostic has one."""
    return d.message + (f" (hint: {d.hint})" if d.hint else "")


@dataclass(frozen=True)
class Context:
    """What a renderer may use besides the report.

    Attributes:
        color: ANSI colours (text only; the caller decides: never for a file or a pipe).
        order: the order of findings (formats that list them one by one).
        robot_line: the text report's first line (which robot checked what).
        robot_json: the JSON report's ``robot`` section and ``stamps`` (with the model hash),
            built only by the formats that ask for it.
    """

    color: bool = False
    order: Order = Order.file
    robot_line: str = ""
    robot_json: Callable[[], dict[str, Any]] = field(default=lambda: {})


def text_column(raw: bytes, column: int, *, utf16: bool) -> int:
    """The 1-based byte ``column`` of source line ``raw`` as a 1-based column in characters
    (Unicode code points), or in UTF-16 code units with ``utf16``. An undecodable byte counts
    as one; a column past the end of the line stays that many past it."""
    head = raw[: max(column - 1, 0)]
    text = head.decode("utf-8", "surrogateescape")
    units = len(text)
    if utf16:
        units += sum(1 for ch in text if ord(ch) > 0xFFFF)
    return units + max(column - 1 - len(head), 0) + 1


PLAIN = Context()
"""No colour, file order, no robot line or section: what a renderer uses when given nothing."""
