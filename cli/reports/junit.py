"""``--format junit``: JUnit XML, one test case per file (CI systems that show test results)."""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
from collections import Counter
from collections.abc import Iterable, Iterator

from motiontool.cli.jsontext import escape_undecodable
from motiontool.cli.reports.common import (
    PLAIN,
    Context,
    shown_counts,
    shown_of,
    summary,
    with_hint,
)
from motiontool.cli.text import plural
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.findings import Findings
from motiontool.motionfmt.validate import FileReport, ValidationReport
from motiontool.stamps import stamps

__all__ = ["render_junit"]


def _line(d: Diagnostic) -> str:
    return f"{d.path}:{d.line}:{d.column}: {d.severity} {d.code}: {with_hint(d)}"


_MARK = "\x01" + os.urandom(8).hex()
"""Marks where a test case's failure (F) or output (O) lines go in the document's skeleton
(unguessable: no file name can hold it)."""
_PLACE = re.compile(_MARK + "([FO])(\\d+)\x01")


def _case(suite: ET.Element, i: int, f: FileReport, shown: Findings, worst: Severity) -> bool:
    """The file's test case (its ``i``-th), with the findings ``shown`` of it: their lines are
    written later, where its placeholders are; True when it fails (a finding at ``worst`` or
    above)."""
    case = ET.SubElement(suite, "testcase", classname="motiontool.validate", name=f.path)
    failing: Counter[Severity] = Counter()
    first, others = None, False
    for d in shown:
        if d.severity >= worst:
            failing[d.severity] += 1
            first = first or d.code
        else:
            others = True
    if first is not None:
        counts = ", ".join(
            plural(failing[sev], str(sev))
            for sev in (Severity.ERROR, Severity.WARNING)
            if failing[sev]
        )
        failure = ET.SubElement(case, "failure", message=counts, type=first)
        failure.text = f"{_MARK}F{i}\x01"
    if others:
        ET.SubElement(case, "system-out").text = f"{_MARK}O{i}\x01"
    return first is not None


def _lines(findings: Iterable[Diagnostic]) -> Iterator[str]:
    """Each finding's line, escaped as XML text (as ElementTree escapes it) and as UTF-8."""
    for d in findings:
        text = _line(d).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
        clean, _count = escape_undecodable(text + "\n")  # a name that is not UTF-8: \xNN
        yield str(clean)


def render_junit(report: ValidationReport, context: Context = PLAIN) -> Iterator[str]:
    """One ``testcase`` per file (``name``: its path; no ``file`` attribute, which Jenkins
    xunit's ``junit-10.xsd`` refuses); a file with an error (a warning too with ``--strict``)
    fails, the failure's ``message`` counting them and its body listing each as
    ``file:line:col: severity CODE: message``. Other findings go to the case's
    ``system-out``, the run's notes and summary to the suite's; the stamps are properties.

    The document is laid out by ElementTree with a placeholder for each case's lines, then
    written with the lines made as they are read (a pass over a file's findings counts them
    for the failure's message first)."""
    worst = Severity.WARNING if context.strict else Severity.ERROR
    suite = ET.Element("testsuite", name="motiontool validate")
    properties = ET.SubElement(suite, "properties")
    for key, value in context.robot_json().get("stamps", stamps()).items():
        ET.SubElement(properties, "property", name=key, value="" if value is None else str(value))
    limits = list(shown_counts(report))  # an int a file: the reports are not held
    failures = sum(
        _case(suite, i, report.files[i], shown_of(report, i, n), worst)
        for i, n in enumerate(limits)
    )
    out = [f"{d.severity} {d.code}: {with_hint(d)}" for d in report.notes] + [summary(report)]
    ET.SubElement(suite, "system-out").text = "\n".join(out) + "\n"
    counts = {"tests": str(len(report.files)), "failures": str(failures), "errors": "0"}
    suite.attrib.update(counts)
    root = ET.Element("testsuites", name="motiontool validate")
    root.attrib.update(counts)
    root.append(suite)
    ET.indent(root)
    skeleton = ET.tostring(root, encoding="unicode", xml_declaration=True) + "\n"
    pieces = _PLACE.split(skeleton)  # text, kind, index, text, kind, index, ..., text
    for k in range(0, len(pieces) - 1, 3):
        yield str(escape_undecodable(pieces[k])[0])
        kind, i = pieces[k + 1], int(pieces[k + 2])
        found = shown_of(report, i, limits[i])
        fails = kind == "F"
        yield from _lines(d for d in found if (d.severity >= worst) == fails)
    yield str(escape_undecodable(pieces[-1])[0])
