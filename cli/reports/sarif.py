"""``--format sarif``: SARIF 2.1.0, as GitHub code scanning and other CI dashboards read it."""

from __future__ import annotations

import os
import urllib.parse
from pathlib import Path
from typing import Any

from motiontool.cli.jsontext import ESCAPED_BYTES, dumps, escape_undecodable
from motiontool.cli.reports.common import PLAIN, Context, findings, text_column, with_hint
from motiontool.motionfmt.diagnostics import CODES, Severity
from motiontool.motionfmt.validate import ValidationReport
from motiontool.stamps import stamps

__all__ = ["SARIF_SRCROOT", "render_sarif"]

SARIF_SRCROOT = "%SRCROOT%"

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


def render_sarif(report: ValidationReport, context: Context = PLAIN) -> str:
    """SARIF 2.1.0, as GitHub code scanning and other CI dashboards read it.

    Columns are in UTF-16 code units (``columnKind`` ``utf16CodeUnits``, SARIF's default),
    converted from the diagnostics' byte columns with the source line. ``properties`` go into
    the run's property bag (next to the stamps).
    """
    order, properties = context.order, context.robot_json()
    used = sorted({d.code for d in report.diagnostics} | set(CODES))
    index = {code: i for i, code in enumerate(used)}
    results = []
    for f, d in findings(report, order):
        raw = f.source_line(d.line)
        region: dict[str, int] = {
            "startLine": max(d.line, 1),
            "startColumn": text_column(raw, d.column, utf16=True),
        }
        if d.end_column and d.end_column >= d.column:
            region["endColumn"] = text_column(raw, d.end_column, utf16=True)
        text = with_hint(d)
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
            "message": {"text": with_hint(d)},
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
