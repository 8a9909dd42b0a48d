"""``--format junit``: JUnit XML, one test case per file (CI systems that show test results)."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from motiontool.cli.jsontext import escape_undecodable
from motiontool.cli.reports.common import PLAIN, Context, per_file, summary, with_hint
from motiontool.cli.text import plural
from motiontool.motionfmt.diagnostics import Diagnostic, Severity
from motiontool.motionfmt.validate import FileReport, ValidationReport
from motiontool.stamps import stamps

__all__ = ["render_junit"]


def _line(d: Diagnostic) -> str:
    return f"{d.path}:{d.line}:{d.column}: {d.severity} {d.code}: {with_hint(d)}"


def _case(suite: ET.Element, f: FileReport, shown: list[Diagnostic], worst: Severity) -> bool:
    """The file's test case, with the findings ``shown`` of it; True when it fails (a finding at
    ``worst`` or above)."""
    case = ET.SubElement(
        suite, "testcase", classname="motiontool.validate", name=f.path, file=f.path
    )
    failing = [d for d in shown if d.severity >= worst]
    if failing:
        counts = ", ".join(
            plural(n, str(sev))
            for sev in (Severity.ERROR, Severity.WARNING)
            if (n := sum(1 for d in failing if d.severity is sev))
        )
        failure = ET.SubElement(case, "failure", message=counts, type=failing[0].code)
        failure.text = "\n".join(_line(d) for d in failing) + "\n"
    others = [d for d in shown if d.severity < worst]
    if others:
        ET.SubElement(case, "system-out").text = "\n".join(_line(d) for d in others) + "\n"
    return bool(failing)


def render_junit(report: ValidationReport, context: Context = PLAIN) -> str:
    """One ``testcase`` per file (``name`` and ``file``: its path); a file with an error (a
    warning too with ``--strict``) fails, the failure's ``message`` counting them and its body
    listing each as ``file:line:col: severity CODE: message``. Other findings go to the case's
    ``system-out``, the run's notes and summary to the suite's; the stamps are properties."""
    worst = Severity.WARNING if context.strict else Severity.ERROR
    suite = ET.Element("testsuite", name="motiontool validate")
    properties = ET.SubElement(suite, "properties")
    for key, value in context.robot_json().get("stamps", stamps()).items():
        ET.SubElement(properties, "property", name=key, value="" if value is None else str(value))
    failures = sum(_case(suite, f, list(shown), worst) for f, shown in per_file(report))
    out = [f"{d.severity} {d.code}: {with_hint(d)}" for d in report.notes] + [summary(report)]
    ET.SubElement(suite, "system-out").text = "\n".join(out) + "\n"
    counts = {"tests": str(len(report.files)), "failures": str(failures), "errors": "0"}
    suite.attrib.update(counts)
    root = ET.Element("testsuites", name="motiontool validate")
    root.attrib.update(counts)
    root.append(suite)
    ET.indent(root)
    text = ET.tostring(root, encoding="unicode", xml_declaration=True)
    clean, _count = escape_undecodable(text + "\n")  # a name that is not UTF-8: \xNN
    return str(clean)
