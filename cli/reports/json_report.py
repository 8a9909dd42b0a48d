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
from motiontool.cli.reports.common import Context, Order, Totals, Writer, fix_json
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport
from motiontool.stamps import stamps

__all__ = ["JSON_SCHEMA_VERSION", "JsonWriter"]

JSON_SCHEMA_VERSION = 1


def _run_json(d: Diagnostic) -> dict[str, Any]:
    """A grouped finding's ``count``, ``end_line``, ``worst`` and ``runs`` where it stands for
    more than one (nothing for one finding)."""
    if d.run is None:
        return {}
    w = d.run.worst
    runs = {"runs": d.run.runs} if d.run.runs > 1 else {}
    return {
        "count": d.run.total,
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


class JsonWriter(Writer):
    """The versioned JSON report; its schema is documented in ``docs/json-report.md`` and
    shipped as ``motiontool/cli/schemas/validate.schema.json``. Written in one pass as the
    findings are made: the files first, then the summary and the run's notes, known once
    every file is validated; the same text as :func:`~motiontool.cli.jsontext.dumps` of the
    whole document."""

    robots_first = True

    def __init__(self, context: Context | None = None) -> None:
        super().__init__(context)
        self.order = Order.file
        self.written = 0
        self.escaped = [0]
        self.doc: dict[str, Any] = {}

    def head(self, totals: Totals | None) -> Iterator[str]:
        self.doc = {
            "schema": "motiontool.validate",
            "schema_version": JSON_SCHEMA_VERSION,
            "stamps": stamps(),
            **self.context.robot_json(),
            "files": HOLE,
            "summary": {},
            "notes": [],
        }
        yield dumps_around(self.doc, 0)[0]

    def file(self, f: FileReport, shown: Iterable[Diagnostic]) -> Iterator[str]:
        yield ("[" if not self.written else ",") + "\n    "
        self.written += 1
        yield from _file(f, shown, self.escaped)

    def tail(self, totals: Totals) -> Iterator[str]:
        yield "\n  ]" if totals.files else "[]"
        self.doc["summary"] = {
            "files": totals.files,
            "errors": totals.found(Severity.ERROR),
            "warnings": totals.found(Severity.WARNING),
            "notes": totals.found(Severity.INFO),
        }
        self.doc["notes"] = [_note_json(d) for d in totals.notes]
        yield text_after(self.doc, self.escaped[0])


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
