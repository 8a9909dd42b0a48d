"""``--format json``: the versioned JSON report (docs/json-report.md; its JSON Schema ships as
``motiontool/cli/schemas/validate.schema.json``)."""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any

from motiontool.cli.jsontext import (
    HOLE,
    dumps_around,
    escape_undecodable,
    indented,
    list_pieces,
    text_after,
)
from motiontool.cli.reports.common import PLAIN, Context, fix_json, per_file
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport, ValidationReport
from motiontool.stamps import stamps

__all__ = ["JSON_SCHEMA_VERSION", "render_json"]

JSON_SCHEMA_VERSION = 1


def _run_json(d: Diagnostic) -> dict[str, Any]:
    """A grouped finding's ``count``, ``end_line``, ``worst`` and ``runs`` where it stands for
    more than one (nothing for one finding)."""
    if d.run is None:
        return {}
    w = d.run.worst
    runs = {"runs": d.run.runs} if d.run.runs > 1 else {}
    return {
        "count": d.run.count,
        "end_line": d.run.end_line,
        **runs,
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


def render_json(report: ValidationReport, context: Context = PLAIN) -> Iterator[str]:
    """The versioned JSON report; its schema is documented in ``docs/json-report.md`` and
    shipped as ``motiontool/cli/schemas/validate.schema.json``. Written in one pass as the
    findings are made: the files first, then the summary and the run's notes, known once
    every file is validated; the same text as :func:`~motiontool.cli.jsontext.dumps` of the
    whole document."""
    doc: dict[str, Any] = {
        "schema": "motiontool.validate",
        "schema_version": JSON_SCHEMA_VERSION,
        "stamps": stamps(),
        **context.robot_json(),
        "files": HOLE,
        "summary": {},
        "notes": [],
    }
    yield dumps_around(doc, 0)[0]
    counter = [0]
    for i, (f, shown) in enumerate(per_file(report)):
        yield ("[" if i == 0 else ",") + "\n    "
        yield from _file(f, shown, counter)
    yield "\n  ]" if report.files else "[]"
    doc["summary"] = {
        "files": len(report.files),
        "errors": report.count(Severity.ERROR),
        "warnings": report.count(Severity.WARNING),
        "notes": report.count(Severity.INFO),
    }
    doc["notes"] = [_note_json(d) for d in report.notes]
    yield text_after(doc, counter[0])


def _file(f: FileReport, shown: Iterable[Diagnostic], escaped: list[int]) -> Iterator[str]:
    """A file's JSON text (an item of the ``files`` list), its findings ``shown`` written as
    they are made; ``escaped[0]`` adds up the undecodable bytes escaped."""
    doc = {
        "path": f.path,
        "accepted_by_webots": f.read.accepted,
        "joints": len(f.read.joints),
        "poses": len(f.read.times_ms),
        "duration_ms": f.read.times_ms[-1] if f.read.times_ms else None,
        "diagnostics": HOLE,
    }
    before, after, n = dumps_around(doc, 2)
    escaped[0] += n
    yield before
    yield from list_pieces(_diagnostic_texts(f, shown, escaped), 3)
    yield after


def _diagnostic_texts(
    f: FileReport, shown: Iterable[Diagnostic], escaped: list[int]
) -> Iterator[str]:
    for d in shown:
        clean, n = escape_undecodable(_diagnostic_json(d, f))
        escaped[0] += n
        yield indented(clean)
