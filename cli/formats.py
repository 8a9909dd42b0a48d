"""Renderings of a validation report: for people (text) and for machines (JSON, SARIF, GitHub)."""

from __future__ import annotations

import enum
import os
import urllib.parse
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import typer

from motiontool.cli.jsontext import ESCAPED_BYTES, dumps, escape_undecodable
from motiontool.cli.text import plural
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport, ValidationReport
from motiontool.stamps import stamps

__all__ = [
    "FORMATS",
    "JSON_SCHEMA_VERSION",
    "Order",
    "render",
    "render_github",
    "render_json",
    "render_sarif",
    "render_text",
    "summary",
]

JSON_SCHEMA_VERSION = 1
FORMATS = ("text", "json", "sarif", "github")
SARIF_SRCROOT = "%SRCROOT%"

_COLORS = {Severity.ERROR: "red", Severity.WARNING: "yellow", Severity.INFO: "cyan"}
_WINDOW = 100  # characters of a long source line shown around the column


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


def _findings(report: ValidationReport, order: Order) -> Iterator[tuple[FileReport, Diagnostic]]:
    pairs = [(f, d) for f in report.files for d in f.diagnostics]
    if order is Order.severity:
        pairs.sort(key=lambda fd: -fd[1].severity)  # stable: file order within a severity
    return iter(pairs)


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
        col += len(prefix)
    gutter = str(d.line)
    pad = " " * len(gutter)
    caret = " " * col + "^" + "~" * max(0, min(width, _WINDOW) - 1)
    return [f" {gutter} | {prefix}{text}", f" {pad} | {_style(caret, color, fg='green')}"]


def render_text(report: ValidationReport, *, color: bool = False, order: Order = Order.file) -> str:
    """Compiler-style lines with the source line and a caret; ANSI colours only with ``color``
    (the caller decides: never for a file or a pipe, see :mod:`motiontool.cli.color`)."""
    out: list[str] = []
    for f, d in _findings(report, order):
        sev = _style(str(d.severity), color, fg=_COLORS[d.severity], bold=True)
        out.append(f"{d.path}:{d.line}:{d.column}: {sev} {d.code}: {d.message}")
        out.extend(_source_excerpt(f, d, color))
        if d.hint:
            out.append(f"   = hint: {d.hint}")
    for d in report.notes:  # about the run, not about a place in a file
        sev = _style(str(d.severity), color, fg=_COLORS[d.severity], bold=True)
        out.append(f"{sev} {d.code}: {d.message}")
        if d.hint:
            out.append(f"   = hint: {d.hint}")
    out.append(summary(report))
    return "\n".join(out) + "\n"


def _diagnostic_json(d: Diagnostic) -> dict[str, Any]:
    return {
        "code": d.code,
        "severity": str(d.severity),
        "line": d.line,
        "column": d.column,
        "end_column": d.end_column,
        "message": d.message,
        "hint": d.hint,
        "joint": d.joint,
        "time_ms": d.time_ms,
    }


def _note_json(d: Diagnostic) -> dict[str, Any]:
    """A note about the run (no file, line or column)."""
    return {"code": d.code, "severity": str(d.severity), "message": d.message, "hint": d.hint}


def render_json(report: ValidationReport, extra: dict[str, Any] | None = None) -> str:
    """The versioned JSON report; its schema is documented in ``docs/json-report.md`` and
    shipped as ``motiontool/cli/schemas/validate.schema.json``."""
    doc: dict[str, Any] = {
        "schema": "motiontool.validate",
        "schema_version": JSON_SCHEMA_VERSION,
        "stamps": stamps(),
        **(extra or {}),
        "summary": {
            "files": len(report.files),
            "errors": report.count(Severity.ERROR),
            "warnings": report.count(Severity.WARNING),
            "notes": report.count(Severity.INFO),
        },
        "notes": [_note_json(d) for d in report.notes],
        "files": [
            {
                "path": f.path,
                "accepted_by_webots": f.read.accepted,
                "joints": len(f.read.joints),
                "poses": len(f.read.times_ms),
                "duration_ms": f.read.times_ms[-1] if f.read.times_ms else None,
                "diagnostics": [_diagnostic_json(d) for d in f.diagnostics],
            }
            for f in report.files
        ],
    }
    return dumps(doc)


def _text_column(raw: bytes, column: int, *, utf16: bool) -> int:
    """The 1-based byte ``column`` of source line ``raw`` as a 1-based column in characters
    (Unicode code points), or in UTF-16 code units with ``utf16``. An undecodable byte counts
    as one; a column past the end of the line stays that many past it."""
    head = raw[: max(column - 1, 0)]
    text = head.decode("utf-8", "surrogateescape")
    units = len(text)
    if utf16:
        units += sum(1 for ch in text if ord(ch) > 0xFFFF)
    return units + max(column - 1 - len(head), 0) + 1


_SARIF_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def _uri(path: str) -> tuple[str, str | None]:
    """The SARIF ``artifactLocation``: a percent-encoded URI reference relative to
    ``%SRCROOT%`` (the working directory) for a file below it, else an absolute ``file://``
    URI; the file's name is encoded as its bytes on disk (UTF-8 or not)."""
    cwd = Path.cwd()
    for candidate in (Path(os.path.abspath(path)), Path(path).resolve()):
        try:
            rel = candidate.relative_to(cwd)
        except ValueError:
            continue
        return urllib.parse.quote(os.fsencode(rel.as_posix()), safe="/"), SARIF_SRCROOT
    return Path(path).resolve().as_uri(), None


def _rule(code: str) -> dict[str, Any]:
    info = CODES.get(code)
    title = info.title if info else code
    level = _SARIF_LEVEL[info.severity] if info else "warning"
    help_text = (
        f"{code}: {title}. Default severity: {level}. 'motiontool codes' lists every code; "
        f"the motiontool README (section 'validate') explains each one. Leave this one out "
        f"with 'motiontool validate --ignore {code}'."
    )
    return {
        "id": code,
        "name": code,
        "shortDescription": {"text": title},
        "fullDescription": {"text": title},
        "help": {"text": help_text},
        "defaultConfiguration": {"level": level},
    }


def render_sarif(
    report: ValidationReport,
    properties: dict[str, Any] | None = None,
    *,
    order: Order = Order.file,
) -> str:
    """SARIF 2.1.0, as GitHub code scanning and other CI dashboards read it.

    Columns are in UTF-16 code units (``columnKind`` ``utf16CodeUnits``, SARIF's default),
    converted from the diagnostics' byte columns with the source line. ``properties`` go into
    the run's property bag (next to the stamps).
    """
    used = sorted({d.code for d in report.diagnostics} | set(CODES))
    index = {code: i for i, code in enumerate(used)}
    results = []
    for f, d in _findings(report, order):
        raw = f.source_line(d.line)
        region: dict[str, int] = {
            "startLine": max(d.line, 1),
            "startColumn": _text_column(raw, d.column, utf16=True),
        }
        if d.end_column and d.end_column >= d.column:
            region["endColumn"] = _text_column(raw, d.end_column, utf16=True)
        text = d.message + (f" (hint: {d.hint})" if d.hint else "")
        uri, base = _uri(d.path)
        location: dict[str, Any] = {"uri": uri}
        if base is not None:
            location["uriBaseId"] = base
        results.append(
            {
                "ruleId": d.code,
                "ruleIndex": index[d.code],
                "level": _SARIF_LEVEL[d.severity],
                "message": {"text": text},
                "locations": [
                    {"physicalLocation": {"artifactLocation": location, "region": region}}
                ],
            }
        )
    notifications = [
        {
            "level": _SARIF_LEVEL[d.severity],
            "message": {"text": d.message + (f" (hint: {d.hint})" if d.hint else "")},
            "descriptor": {"id": d.code, "index": index[d.code]},
        }
        for d in report.notes
    ]
    run: dict[str, Any] = {
        "invocations": [{"executionSuccessful": True, "toolExecutionNotifications": notifications}],
        "tool": {
            "driver": {
                "name": "motiontool",
                "version": stamps()["motiontool"],
                "informationUri": "https://pypi.org/project/motiontool/",
                "rules": [_rule(code) for code in used],
            }
        },
        "originalUriBaseIds": {SARIF_SRCROOT: {"uri": Path.cwd().as_uri().rstrip("/") + "/"}},
        "columnKind": "utf16CodeUnits",
        "results": results,
        "properties": {"stamps": stamps(), **(properties or {})},
    }
    doc = {
        "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
        "version": "2.1.0",
        "runs": [run],
    }
    clean, count = escape_undecodable(doc)
    if count:
        clean["runs"][0]["properties"][ESCAPED_BYTES] = count
    return dumps(clean, count_field=False)


def _gh_escape(text: str, *, prop: bool = False) -> str:
    text = text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")
    if prop:
        text = text.replace(":", "%3A").replace(",", "%2C")
    return text


_GH_COMMAND = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def render_github(report: ValidationReport, *, order: Order = Order.file) -> str:
    """GitHub Actions workflow commands: one annotation per diagnostic, then a summary.

    ``col`` and ``endColumn`` count characters (GitHub's unit), converted from byte columns;
    a run's note (a check skipped for a missing library) is an annotation without a file.
    """
    out = []
    for f, d in _findings(report, order):
        raw = f.source_line(d.line)
        col = _text_column(raw, d.column, utf16=False)
        props = [f"file={_gh_escape(d.path, prop=True)}", f"line={d.line}", f"col={col}"]
        if d.end_column and d.end_column >= d.column:
            props.append(f"endColumn={_text_column(raw, d.end_column, utf16=False)}")
        title = f"{d.code} {CODES[d.code].title}" if d.code in CODES else d.code
        props.append(f"title={_gh_escape(title, prop=True)}")
        text = d.message + (f" (hint: {d.hint})" if d.hint else "")
        out.append(f"::{_GH_COMMAND[d.severity]} {','.join(props)}::{_gh_escape(text)}")
    for d in report.notes:  # about the run: an annotation without a file
        title = _gh_escape(f"{d.code} {CODES[d.code].title}", prop=True)
        text = d.message + (f" (hint: {d.hint})" if d.hint else "")
        out.append(f"::{_GH_COMMAND[d.severity]} title={title}::{_gh_escape(text)}")
    out.append(summary(report))
    # A name that is not UTF-8 is written as \xNN, as in the JSON and SARIF reports: the
    # runner reads the log as UTF-8.
    text, _count = escape_undecodable("\n".join(out) + "\n")
    return str(text)


def render(
    report: ValidationReport, fmt: str, *, color: bool = False, order: Order = Order.file
) -> str:
    """Render ``report`` in one of :data:`FORMATS` (``color`` only affects text; ``order``
    text, GitHub and SARIF: the JSON report is grouped by file)."""
    if fmt == "text":
        return render_text(report, color=color, order=order)
    if fmt == "json":
        return render_json(report)
    if fmt == "sarif":
        return render_sarif(report, order=order)
    if fmt == "github":
        return render_github(report, order=order)
    raise ValueError(f"unknown format {fmt!r}; choose one of {', '.join(FORMATS)}")
