"""``--format json``: the versioned JSON report (docs/json-report.md; its JSON Schema ships as
``motiontool/cli/schemas/validate.schema.json``)."""

from __future__ import annotations

from typing import Any

from motiontool.cli.jsontext import dumps
from motiontool.cli.reports.common import PLAIN, Context, fix_json
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport, ValidationReport
from motiontool.stamps import stamps

__all__ = ["JSON_SCHEMA_VERSION", "render_json"]

JSON_SCHEMA_VERSION = 1


def _run_json(d: Diagnostic) -> dict[str, Any]:
    """A grouped finding's ``count``, ``end_line`` and ``worst`` (nothing for one finding)."""
    if d.run is None:
        return {}
    w = d.run.worst
    return {
        "count": d.run.count,
        "end_line": d.run.end_line,
        "worst": {
            "value": w.value,
            "unit": w.unit,
            "line": w.line,
            "column": w.column,
            "time_ms": w.time_ms,
        },
    }


def _diagnostic_json(d: Diagnostic, f: FileReport) -> dict[str, Any]:
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
        "fix": fix_json(f.fix_of(d)),
        **_run_json(d),
    }


def _note_json(d: Diagnostic) -> dict[str, Any]:
    """A note about the run (no file, line or column)."""
    return {"code": d.code, "severity": str(d.severity), "message": d.message, "hint": d.hint}


def render_json(report: ValidationReport, context: Context = PLAIN) -> str:
    """The versioned JSON report; its schema is documented in ``docs/json-report.md`` and
    shipped as ``motiontool/cli/schemas/validate.schema.json``."""
    doc: dict[str, Any] = {
        "schema": "motiontool.validate",
        "schema_version": JSON_SCHEMA_VERSION,
        "stamps": stamps(),
        **context.robot_json(),
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
                "diagnostics": [_diagnostic_json(d, f) for d in f.diagnostics],
            }
            for f in report.files
        ],
    }
    return dumps(doc)
