"""``--format sarif``: SARIF 2.1.0, as GitHub code scanning and other CI dashboards read it."""

from __future__ import annotations

import functools
import os
import urllib.parse
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

from motiontool.cli.jsontext import (
    HOLE,
    JsonList,
    dumps_around,
    escape_undecodable,
    indented,
    text_after,
)
from motiontool.cli.reports.common import (
    Context,
    Fingerprints,
    Totals,
    Writer,
    project_root,
    relative_path,
    text_column,
    with_hint,
)
from motiontool.cli.rules import RULES
from motiontool.motionfmt.diagnostics import CODES, Diagnostic, Related, Severity
from motiontool.motionfmt.fixes import Fix
from motiontool.motionfmt.validate import FileReport
from motiontool.stamps import stamps

__all__ = [
    "FINGERPRINT_KEY",
    "HOME_LABEL",
    "RULES_LABEL",
    "SARIF_SRCROOT",
    "SarifWriter",
    "project_urls",
]

SARIF_SRCROOT = "%SRCROOT%"
FINGERPRINT_KEY = "motiontoolFinding/v1"
"""The key of a result's ``partialFingerprints``: code, path and message, not the line."""

_SARIF_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}

HOME_LABEL = "Homepage"
"""The project URL (pyproject.toml's ``[project.urls]``) that is the driver's
``informationUri``."""
RULES_LABEL = "Rules"
"""The project URL of docs/rules.md as published: a rule's ``helpUri`` is its section there
(``#mt106``)."""


def project_urls() -> dict[str, str]:
    """The installed package's project URLs by label (pyproject.toml's ``[project.urls]``, read
    from its metadata as the version stamps are), or none where it is not installed. The
    repository is not published yet: while pyproject.toml names no URL, SARIF has no link
    rather than one that goes nowhere."""
    from importlib import metadata

    try:
        entries = metadata.metadata("motiontool").get_all("Project-URL") or []
    except metadata.PackageNotFoundError:
        return {}
    return dict(entry.split(", ", 1) for entry in entries if ", " in entry)


def _uri(path: str) -> tuple[str, str | None]:
    """The SARIF ``artifactLocation``: a percent-encoded URI reference relative to
    ``%SRCROOT%`` (the repository root, :func:`~motiontool.cli.reports.common.project_root`)
    for a file below it, else an absolute ``file://`` URI; the file's name is encoded as its
    bytes on disk (UTF-8 or not). Found once per path and working directory."""
    return _uri_from(os.getcwd(), path)


@functools.lru_cache(maxsize=4096)
def _uri_from(cwd: str, path: str) -> tuple[str, str | None]:
    rel = relative_path(path)
    if rel is not None:
        return urllib.parse.quote(os.fsencode(rel.as_posix()), safe="/"), SARIF_SRCROOT
    return Path(path).resolve().as_uri(), None


def _rule(code: str, rules_url: str | None) -> dict[str, Any]:
    info = CODES.get(code)
    title = info.title if info else code
    level = _SARIF_LEVEL[info.severity] if info else "warning"
    explained = RULES.get(code)
    webots = f" {explained.webots}" if explained else ""
    fix = f" Fix: {explained.fix}." if explained else ""
    help_text = (
        f"{code}: {title}.{webots}{fix} Default severity: {level}. 'motiontool rule {code}' "
        f"shows an example and its fix. Leave this one out with "
        f"'motiontool validate --ignore {code}'."
    )
    help_markdown = (
        f"**{code}**: {title}.\n\n{webots.strip()}\n\n{fix.strip()}\n\n"
        f"Default severity: `{level}`. `motiontool rule {code}` shows an example and its fix.\n\n"
        f"Leave this one out with `motiontool validate --ignore {code}`."
    )
    rule: dict[str, Any] = {
        "id": code,
        "name": code,
        "shortDescription": {"text": title},
        "fullDescription": {"text": title},
        "help": {"text": help_text, "markdown": help_markdown},
        "defaultConfiguration": {"level": level},
    }
    if rules_url is not None:  # its section of docs/rules.md (a heading "## MT106")
        rule["helpUri"] = f"{rules_url}#{code.lower()}"
    return rule


def _result(f: FileReport, d: Diagnostic, rule: int, fingerprint: str) -> dict[str, Any]:
    """One finding: its rule, level, message, place (columns in UTF-16 code units) and a
    fingerprint that survives lines added above it."""
    raw = f.source_line(d.line)
    region: dict[str, int] = {
        "startLine": max(d.line, 1),
        "startColumn": text_column(raw, d.column, utf16=True),
    }
    if d.end_column and d.end_column >= d.column:
        region["endColumn"] = text_column(raw, d.end_column, utf16=True)
    uri, base = _uri(d.path)
    location: dict[str, Any] = {"uri": uri}
    if base is not None:
        location["uriBaseId"] = base
    fixes, left = _fixes(f, d, location)
    result: dict[str, Any] = {
        "ruleId": d.code,
        "ruleIndex": rule,
        "level": _SARIF_LEVEL[d.severity],
        "message": {"text": with_hint(d)},
        "locations": [{"physicalLocation": {"artifactLocation": location, "region": region}}],
        "partialFingerprints": {FINGERPRINT_KEY: fingerprint},
        **fixes,
        **_run(f, d, location),
    }
    if d.related:  # the lines its message names: where they are now, out of the fingerprint
        held = result.get("relatedLocations", [])
        named = enumerate(d.related, len(held) + 1)
        result["relatedLocations"] = [*held, *(_related(f, r, location, i) for i, r in named)]
    if left:  # a fix too large to carry: left to validate --fix, counted
        result.setdefault("properties", {})["fixEdits"] = left
    return result


def _run(f: FileReport, d: Diagnostic, location: dict[str, Any]) -> dict[str, Any]:
    """A grouped finding's worst pose as a related location, and its ``count``, ``endLine``,
    ``runs`` (where it stands for more than one) and ``worst`` in the result's properties
    (nothing for one finding)."""
    if d.run is None:
        return {}
    w = d.run.worst
    region = {
        "startLine": w.line,
        "startColumn": text_column(f.source_line(w.line), w.column, utf16=True),
    }
    worst = {"value": w.value, "unit": w.unit, "line": w.line, "timeMs": w.time_ms}
    related = {
        "id": 1,
        "message": {"text": f"worst: {w.value:.6g} {w.unit}"},
        "physicalLocation": {"artifactLocation": location, "region": region},
    }
    properties: dict[str, Any] = {"count": d.run.total, "endLine": d.run.end_line}
    if d.run.runs > 1:
        properties["runs"] = d.run.runs
    properties["worst"] = worst
    return {"relatedLocations": [related], "properties": properties}


def _related(f: FileReport, r: Related, location: dict[str, Any], i: int) -> dict[str, Any]:
    """A place a finding's message names, as its ``i``-th related location."""
    region = {
        "startLine": r.line,
        "startColumn": text_column(f.source_line(r.line), r.column, utf16=True),
    }
    return {
        "id": i,
        "message": {"text": r.message},
        "physicalLocation": {"artifactLocation": location, "region": region},
    }


def _replacement(f: FileReport, fix: Fix) -> dict[str, Any]:
    """One edit as a SARIF replacement: the deleted region (UTF-16 columns) and the text."""
    raw = f.source_line(fix.line)
    start = text_column(raw, fix.column, utf16=True)
    if fix.replacement is None:  # the whole line, and its end
        region = {"startLine": fix.line, "startColumn": 1, "endLine": fix.line + 1}
        return {"deletedRegion": {**region, "endColumn": 1}}
    end_byte = len(raw) + 1 if fix.end_column is None else fix.end_column
    region = {"startLine": fix.line, "startColumn": start}
    region["endColumn"] = text_column(raw, end_byte, utf16=True)
    text = fix.replacement.decode("utf-8", "surrogateescape")
    return {"deletedRegion": region, "insertedContent": {"text": text}}


MAX_FIX_EDITS = 1000
"""Most edits a result's ``fixes`` carries. A larger fix (a grouped finding over thousands of
poses: 33 000 clamps) is left to ``validate --fix`` and counted in the result's properties
(``fixEdits``): GitHub code scanning refuses a SARIF file over 10 MB compressed, and no
editor applies such a fix from a dashboard."""


def _fixes(f: FileReport, d: Diagnostic, location: dict[str, Any]) -> tuple[dict[str, Any], int]:
    """``fixes`` of a result with a fix: its description (unsafe ones say so) and edits; and
    how many edits a fix of more than :data:`MAX_FIX_EDITS` has, left out (else 0)."""
    count = f.fix_count(d)
    if count > MAX_FIX_EDITS:
        return {}, count
    fixes = f.fix_of(d)
    if not fixes:
        return {}, 0
    safe = all(x.safe for x in fixes)
    text = fixes[0].title + ("" if safe else " (unsafe: it changes what the robot does)")
    change = {"artifactLocation": location, "replacements": [_replacement(f, x) for x in fixes]}
    return {"fixes": [{"description": {"text": text}, "artifactChanges": [change]}]}, 0


class SarifWriter(Writer):
    """SARIF 2.1.0, as GitHub code scanning and other CI dashboards read it, its results
    written as the findings are made.

    Columns are in UTF-16 code units (``columnKind`` ``utf16CodeUnits``, SARIF's default),
    converted from the diagnostics' byte columns with the source line; URIs are relative to
    the repository root. The robot section goes into the run's property bag (next to the
    stamps); a run's notes into the invocation's ``toolExecutionNotifications``: both after
    the results, once every file is validated (one pass over the files).
    """

    def __init__(self, context: Context | None = None) -> None:
        super().__init__(context)
        used = sorted(CODES)  # every code a finding may have: no pass over the findings for it
        self.index = {code: i for i, code in enumerate(used)}
        self.used = used
        self.results = JsonList(3)
        self.escaped = 0
        self.fingerprint = Fingerprints()
        self.run: dict[str, Any] = {}
        self.doc: dict[str, Any] = {}

    def head(self, totals: Totals | None) -> Iterator[str]:
        urls = project_urls()
        driver: dict[str, Any] = {"name": "motiontool", "version": stamps()["motiontool"]}
        if HOME_LABEL in urls:
            driver["informationUri"] = urls[HOME_LABEL]
        driver["rules"] = [_rule(code, urls.get(RULES_LABEL)) for code in self.used]
        root = project_root().as_uri().rstrip("/") + "/"
        self.run = {
            "tool": {"driver": driver},
            "originalUriBaseIds": {SARIF_SRCROOT: {"uri": root}},
            "columnKind": "utf16CodeUnits",
            "results": HOLE,
            "invocations": [],  # after the results: the run's notes and robots are known then
            "properties": {},
        }
        self.doc = {
            "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
            "version": "2.1.0",
            "runs": [self.run],
        }
        yield dumps_around(self.doc, 0)[0]

    def file(self, f: FileReport, shown: Iterable[Diagnostic]) -> Iterator[str]:
        """Each finding's result as JSON text, made as the findings are."""
        for d in shown:
            fingerprint = self.fingerprint(d, self.order)
            clean, n = escape_undecodable(_result(f, d, self.index[d.code], fingerprint))
            self.escaped += n
            yield self.results.item(indented(clean))

    def tail(self, totals: Totals) -> Iterator[str]:
        yield self.results.close()
        notifications = [
            {
                "level": _SARIF_LEVEL[d.severity],
                "message": {"text": with_hint(d)},
                "descriptor": {"id": d.code, "index": self.index[d.code]},
            }
            for d in totals.notes
        ]
        self.run["invocations"] = [
            {"executionSuccessful": True, "toolExecutionNotifications": notifications}
        ]
        properties: dict[str, Any] = {"stamps": stamps(), **self.context.robot_json()}
        self.run["properties"] = properties
        yield text_after(self.doc, self.escaped, count_in=properties)  # the count in the bag
