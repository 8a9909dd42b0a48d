"""Renderings of a validation report: for people (text) and for machines (JSON, SARIF, GitHub)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import typer

from motiontool.cli.stamps import stamps
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport, ValidationReport

__all__ = ["FORMATS", "JSON_SCHEMA_VERSION", "render"]

JSON_SCHEMA_VERSION = 1
FORMATS = ("text", "json", "sarif", "github")

_COLORS = {Severity.ERROR: "red", Severity.WARNING: "yellow", Severity.INFO: "cyan"}
_WINDOW = 100  # characters of a long source line shown around the column


def _plural(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def summary(report: ValidationReport) -> str:
    """``checked 3 files: 1 error, 2 warnings, 0 notes``."""
    return (
        f"checked {_plural(len(report.files), 'file')}: "
        f"{_plural(report.count(Severity.ERROR), 'error')}, "
        f"{_plural(report.count(Severity.WARNING), 'warning')}, "
        f"{_plural(report.count(Severity.INFO), 'note')}"
    )


def _source_excerpt(report: FileReport, d: Diagnostic) -> list[str]:
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
    return [f" {gutter} | {prefix}{text}", f" {pad} | {typer.style(caret, fg='green')}"]


def render_text(report: ValidationReport) -> str:
    out: list[str] = []
    for f in report.files:
        for d in f.diagnostics:
            sev = typer.style(str(d.severity), fg=_COLORS[d.severity], bold=True)
            out.append(f"{d.path}:{d.line}:{d.column}: {sev} {d.code}: {d.message}")
            out.extend(_source_excerpt(f, d))
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


def render_json(report: ValidationReport, extra: dict[str, Any] | None = None) -> str:
    """The versioned JSON report; its schema is documented in ``docs/json-report.md``."""
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
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


_SARIF_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def _uri(path: str) -> str:
    p = Path(path)
    try:
        rel = p.resolve().relative_to(Path.cwd().resolve())
    except ValueError:
        return p.resolve().as_uri()
    return rel.as_posix()


def render_sarif(report: ValidationReport) -> str:
    """SARIF 2.1.0, as GitHub code scanning and other CI dashboards read it."""
    used = sorted({d.code for d in report.diagnostics} | set(CODES))
    index = {code: i for i, code in enumerate(used)}
    rules = [
        {
            "id": code,
            "name": code,
            "shortDescription": {"text": CODES[code].title if code in CODES else code},
            "defaultConfiguration": {
                "level": _SARIF_LEVEL[CODES[code].severity] if code in CODES else "warning"
            },
        }
        for code in used
    ]
    results = []
    for d in report.diagnostics:
        region: dict[str, int] = {"startLine": d.line, "startColumn": d.column}
        if d.end_column:
            region["endColumn"] = d.end_column
        text = d.message + (f" (hint: {d.hint})" if d.hint else "")
        results.append(
            {
                "ruleId": d.code,
                "ruleIndex": index[d.code],
                "level": _SARIF_LEVEL[d.severity],
                "message": {"text": text},
                "locations": [
                    {
                        "physicalLocation": {
                            "artifactLocation": {"uri": _uri(d.path)},
                            "region": region,
                        }
                    }
                ],
            }
        )
    doc = {
        "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
        "version": "2.1.0",
        "runs": [
            {
                "tool": {
                    "driver": {
                        "name": "motiontool",
                        "version": stamps()["motiontool"],
                        "informationUri": "https://pypi.org/project/motiontool/",
                        "rules": rules,
                    }
                },
                "columnKind": "unicodeCodePoints",
                "results": results,
                "properties": {"stamps": stamps()},
            }
        ],
    }
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def _gh_escape(text: str, *, prop: bool = False) -> str:
    text = text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")
    if prop:
        text = text.replace(":", "%3A").replace(",", "%2C")
    return text


_GH_COMMAND = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def render_github(report: ValidationReport) -> str:
    """GitHub Actions workflow commands: one annotation per diagnostic, then a summary."""
    out = []
    for d in report.diagnostics:
        props = [f"file={_gh_escape(d.path, prop=True)}", f"line={d.line}", f"col={d.column}"]
        if d.end_column:
            props.append(f"endColumn={d.end_column}")
        title = f"{d.code} {CODES[d.code].title}" if d.code in CODES else d.code
        props.append(f"title={_gh_escape(title, prop=True)}")
        text = d.message + (f" (hint: {d.hint})" if d.hint else "")
        out.append(f"::{_GH_COMMAND[d.severity]} {','.join(props)}::{_gh_escape(text)}")
    out.append(summary(report))
    return "\n".join(out) + "\n"


_RENDERERS = {
    "text": render_text,
    "json": render_json,
    "sarif": render_sarif,
    "github": render_github,
}


def render(report: ValidationReport, fmt: str) -> str:
    """Render ``report`` in one of :data:`FORMATS`."""
    return _RENDERERS[fmt](report)
