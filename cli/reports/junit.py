"""``--format junit``: JUnit XML, one test case per file (CI systems that show test results)."""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
from collections import Counter
from collections.abc import Iterable, Iterator

from motiontool.cli.jsontext import escape_undecodable
from motiontool.cli.reports.common import (
    Context,
    Order,
    Totals,
    Writer,
    summary,
    with_hint,
)
from motiontool.cli.text import plural
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport
from motiontool.stamps import stamps

__all__ = ["JunitWriter"]


def _line(d: Diagnostic) -> str:
    return f"{d.path}:{d.line}:{d.column}: {d.severity} {d.code}: {with_hint(d)}"


_MARK = "\x01" + os.urandom(8).hex()
"""Marks where a test case's failure (F) or output (O) lines go in the document's skeleton
(unguessable: no file name can hold it)."""
_PLACE = re.compile(_MARK + "([FO])(\\d+)\x01")


def _case(
    suite: ET.Element, i: int, f: FileReport, shown: Iterable[Diagnostic], worst: Severity
) -> bool:
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


class JunitWriter(Writer):
    """One ``testcase`` per file (``name``: its path; no ``file`` attribute, which Jenkins
    xunit's ``junit-10.xsd`` refuses); a file with an error (a warning too with ``--strict``)
    fails, the failure's ``message`` counting them and its body listing each as
    ``file:line:col: severity CODE: message``. Other findings go to the case's
    ``system-out``, the run's notes and summary to the suite's; the stamps are properties.

    The document is laid out by ElementTree with a placeholder for each case's lines (a first
    pass over the files, :meth:`count`: how many fail), then written with the lines made as
    they are read (a second pass over the files with findings)."""

    counts_first = True

    def __init__(self, context: Context | None = None) -> None:
        super().__init__(context)
        self.order = Order.file
        self.worst = Severity.WARNING if self.context.strict else Severity.ERROR
        self.suite = ET.Element("testsuite", name="motiontool validate")
        self.properties = ET.SubElement(self.suite, "properties")  # filled in by the head
        self.cases = self.failures = 0
        self.pieces: list[str] = []
        self.at = 0  # the piece written last

    def count(self, f: FileReport, shown: Iterable[Diagnostic]) -> None:
        self.failures += _case(self.suite, self.cases, f, shown, self.worst)
        self.cases += 1

    def head(self, totals: Totals | None) -> Iterator[str]:
        assert totals is not None
        for key, value in self.context.robot_json().get("stamps", stamps()).items():
            value = "" if value is None else str(value)
            ET.SubElement(self.properties, "property", name=key, value=value)
        out = [f"{d.severity} {d.code}: {with_hint(d)}" for d in totals.notes]
        ET.SubElement(self.suite, "system-out").text = "\n".join([*out, summary(totals)]) + "\n"
        counts = {"tests": str(totals.files), "failures": str(self.failures), "errors": "0"}
        self.suite.attrib.update(counts)
        root = ET.Element("testsuites", name="motiontool validate")
        root.attrib.update(counts)
        root.append(self.suite)
        ET.indent(root)
        skeleton = ET.tostring(root, encoding="unicode", xml_declaration=True) + "\n"
        self.pieces = _PLACE.split(skeleton)  # text, kind, index, text, kind, index, ..., text
        yield str(escape_undecodable(self.pieces[0])[0])

    def file(self, f: FileReport, shown: Iterable[Diagnostic]) -> Iterator[str]:
        """The lines of the next file with findings, where its placeholders are (failures,
        then output), each followed by the document's text up to the next placeholder."""
        pieces, first = self.pieces, self.at
        while self.at + 2 < len(pieces) and pieces[self.at + 2] == pieces[first + 2]:
            fails = pieces[self.at + 1] == "F"
            yield from _lines(d for d in shown if (d.severity >= self.worst) == fails)
            yield str(escape_undecodable(pieces[self.at + 3])[0])
            self.at += 3
