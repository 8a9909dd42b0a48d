"""``--format text``: compiler-style lines with the source line and a caret, for people."""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any

import typer

from motiontool.cli.reports.common import (
    Context,
    FixCounts,
    Totals,
    Writer,
    fix_summary,
    summary,
)
from motiontool.cli.text import escaped
from motiontool.cli.text import shown as shown_
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport

__all__ = ["TextWriter"]

_COLORS = {Severity.ERROR: "red", Severity.WARNING: "yellow", Severity.INFO: "cyan"}
_WINDOW = 100  # characters of a long source line shown around the column


def _style(text: str, color: bool, **how: Any) -> str:
    return typer.style(text, **how) if color else text


def _source_excerpt(report: FileReport, d: Diagnostic, color: bool) -> list[str]:
    raw = report.source_line(d.line)
    if not raw and d.line > 1:
        return []
    text = raw.decode("utf-8", "replace").replace("\t", " ")
    start = raw[: max(d.column - 1, 0)].decode("utf-8", "replace")
    col = len(start)
    width = 1
    if d.end_column and d.end_column > d.column:
        width = len(raw[d.column - 1 : d.end_column - 1].decode("utf-8", "replace"))
    prefix = ""
    if len(text) > _WINDOW:
        lo = max(0, col - _WINDOW // 2)
        text = text[lo : lo + _WINDOW]
        col -= lo
        prefix = "..." if lo else ""
    # control characters shown escaped (an ESC in a name would act on the terminal); the caret
    # moves with the text before it, and widens with the text under it
    width = len(escaped(text[col : col + width])) if width > 1 else width
    col = len(prefix) + len(escaped(text[:col]))
    text = escaped(text)
    gutter = str(d.line)
    pad = " " * len(gutter)
    caret = " " * col + "^" + "~" * max(0, min(width, _WINDOW) - 1)
    return [f" {gutter} | {prefix}{text}", f" {pad} | {_style(caret, color, fg='green')}"]


def _fix_line(summary: tuple[bool, str] | None) -> list[str]:
    """``   = fix (--fix): write '2'`` where a fix exists (``summary``: the finding's
    :meth:`~FileReport.fix_summary`); the compiler line stays as it is, so editors' problem
    matchers read it unchanged."""
    if summary is None:
        return []
    safe, title = summary
    return [f"   = fix ({'--fix' if safe else '--fix --unsafe-fixes'}): {title}"]


def _mark(summary: tuple[bool, str] | None) -> str:
    """``[*] `` before the message of a finding ``--fix`` fixes, as ruff marks it (an unsafe
    fix is not marked: ``--fix`` alone leaves it); after the code and its colon, so that
    editors' problem matchers read the code as before."""
    return "[*] " if summary is not None and summary[0] else ""


class TextWriter(Writer):
    """The robot line, then compiler-style lines with the source line and a caret, a finding
    at a time as they are made; ANSI colours only with ``context.color`` (never for a file or
    a pipe, see :mod:`motiontool.cli.color`)."""

    def __init__(self, context: Context | None = None) -> None:
        super().__init__(context)
        self.robots_first = not self.context.quiet
        self.fixable = FixCounts()

    def head(self, totals: Totals | None) -> Iterator[str]:
        robot_line = "" if self.context.quiet else self.context.robot_line()
        if robot_line:
            yield robot_line.rstrip("\n") + "\n"

    def file(self, f: FileReport, shown: Iterable[Diagnostic]) -> Iterator[str]:
        color = self.context.color
        for d in shown:
            sev = _style(str(d.severity), color, fg=_COLORS[d.severity], bold=True)
            fix = f.fix_summary(d)
            out = [f"{d.path}:{d.line}:{d.column}: {sev} {d.code}: {_mark(fix)}{shown_(d.message)}"]
            out.extend(_source_excerpt(f, d, color))
            if d.hint:
                out.append(f"   = hint: {shown_(d.hint)}")
            self.fixable.add(fix)
            out.extend(_fix_line(fix))
            out.append("")
            yield "\n".join(out)

    def tail(self, totals: Totals) -> Iterator[str]:
        color, out = self.context.color, []
        for d in totals.notes:  # about the run, not about a place in a file
            sev = _style(str(d.severity), color, fg=_COLORS[d.severity], bold=True)
            out.append(f"{sev} {d.code}: {shown_(d.message)}")
            if d.hint:
                out.append(f"   = hint: {shown_(d.hint)}")
        if not self.context.quiet:
            out.append(summary(totals) + fix_summary(self.fixable))
        if out:
            yield "\n".join(out) + "\n"
