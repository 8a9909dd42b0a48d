"""``motiontool rule [CODE]``: what a diagnostic code means, with an example and its fix; and
``motiontool codes``: every code, one line each (what ``rule`` without a code lists too)."""

from __future__ import annotations

import shlex
import textwrap
from typing import Annotated, Any

import typer

from motiontool.cli.jsontext import dumps
from motiontool.cli.options import TextOrJson, TextOrJsonOption
from motiontool.cli.rules import RULES, Example, Rule, rule
from motiontool.motionfmt.diagnostics import CODES

__all__ = [
    "checks_table",
    "codes_command",
    "codes_table",
    "codes_text",
    "rule_command",
    "rules_markdown",
]

_WIDTH = 100
_SHOWN = 60
"""Characters of a longer example line shown before it is cut."""
_AUTOFIX = {
    "safe": "yes, a safe fix (Webots then sends exactly the same commands)",
    "unsafe": "only with --unsafe-fixes (it changes what the robot does)",
    None: "no",
}

_Code = Annotated[
    str | None,
    typer.Argument(help="A diagnostic code (MT303); none: list every code.", show_default=False),
]


def _line(raw: bytes) -> str:
    """One line of an example as text: bytes that are not UTF-8 and control characters as
    ``\\xNN``, a line longer than the terminal cut with its length in bytes."""
    text = raw.decode("utf-8", "backslashreplace")
    text = "".join(f"\\x{ord(c):02x}" if ord(c) < 0x20 or c == "\x7f" else c for c in text)
    if len(text) > _WIDTH - 2:
        return f"{text[:_SHOWN]}... ({len(raw):,} bytes)"
    return text


def _file_text(data: bytes) -> list[str]:
    """A file shown indented, line by line (``(an empty file)`` for none)."""
    if not data:
        return ["  (an empty file)"]
    lines = data.split(b"\n")
    if lines[-1] == b"":
        lines.pop()
    return [f"  {_line(raw)}" for raw in lines]


def _command(example: Example) -> str:
    return shlex.join(["motiontool", "validate", *example.args, example.name])


def _wrapped(label: str, text: str) -> list[str]:
    return textwrap.wrap(f"{label} {text}", _WIDTH, subsequent_indent="  ")


def _text(entry: Rule) -> str:
    example = entry.example
    info = CODES[entry.code]
    out = [f"{entry.code}  {info.severity}  {info.title}", ""]
    out += _wrapped("Webots:", entry.webots)
    without = "".join(f", {m} not installed" for m in example.missing)
    out.append(f"Example ({_command(example)}{without}):")
    out += _file_text(example.data)
    for name, data in example.siblings:
        out.append(f"Beside it, {name}:")
        out += _file_text(data)
    out += _wrapped("Fix:", entry.fix)
    if entry.fixed is not None:
        out.append("Fixed:")
        out += _file_text(entry.fixed)
    out.append(f"validate --fix: {_AUTOFIX[entry.autofix]}")
    return "\n".join(out) + "\n"


def rules_markdown() -> str:
    """docs/rules.md: every code's explanation as ``motiontool rule CODE`` prints it, each
    under a heading of its own (``## MT106``, GitHub's anchor ``#mt106``: where SARIF's
    ``helpUri`` points); written by ``python dev/rules_doc.py``."""
    head = (
        "# Diagnostic codes: `motiontool codes`, `motiontool rule`\n\n"
        "Every code `motiontool validate` reports, as `motiontool rule CODE` prints it: what"
        " Webots does,\nan example that triggers it, its fix, and whether `validate --fix`"
        " applies it. Made from the\nrule records (`cli/rules_syntax.py`, `cli/rules_traps.py`,"
        " `cli/rules_robot.py`) by\n`python dev/rules_doc.py`: edit those, not this file.\n"
    )
    return head + "".join(f"\n## {e.code}\n\n```text\n{_text(e)}```\n" for e in RULES.values())


def codes_table() -> str:
    """The codes table of docs/commands.md (Markdown): one row per :attr:`Rule.row`, with the
    codes that share it and their severities; written by ``python dev/rules_doc.py``."""
    groups: list[list[Rule]] = []
    for entry in RULES.values():
        if entry.row is None and groups:
            groups[-1].append(entry)
        else:
            groups.append([entry])
    out = ["| code | severity | what |", "|---|---|---|"]
    for group in groups:
        ids = [e.code for e in group]
        label = ids[0] if len(ids) == 1 else ", ".join(ids) if len(ids) == 2 else ""
        label = label or f"{ids[0]}–{ids[-1]}"
        severities: list[str] = []
        for info in (CODES[i] for i in ids):
            for sev in (info.severity, info.also):
                if sev is not None and str(sev) not in severities:
                    severities.append(str(sev))
        out.append(f"| {label} | {' / '.join(severities)} | {group[0].row} |")
    return "\n".join(out) + "\n"


def checks_table() -> str:
    """The robot checks table of docs/commands.md (Markdown), one row per entry of
    :data:`~motiontool.kinematics.checks.registry.CHECK_REGISTRY`."""
    from motiontool.kinematics.checks import CHECK_REGISTRY

    out = ["| check | default | needs | codes | what |", "|---|---|---|---|---|"]
    for c in CHECK_REGISTRY:
        needs = "core" if c.extra is None else f"`motiontool[{c.extra}]`"
        default = "yes" if c.default else "no"
        out.append(f"| `{c.name}` | {default} | {needs} | {', '.join(c.codes)} | {c.summary} |")
    return "\n".join(out) + "\n"


def _show(data: bytes) -> str:
    """A file's bytes for the JSON report, which writes each undecodable byte as ``\\xNN``
    and counts them in ``escaped_bytes`` (:func:`~motiontool.cli.jsontext.dumps`)."""
    return data.decode("utf-8", "surrogateescape")


def _json(entry: Rule) -> dict[str, Any]:
    example = entry.example
    return {
        "code": entry.code,
        "severity": str(CODES[entry.code].severity),
        "title": CODES[entry.code].title,
        "webots": entry.webots,
        "example": {
            "name": example.name,
            "file": _show(example.data),
            "command": _command(example),
            "siblings": [{"name": n, "file": _show(d)} for n, d in example.siblings],
            "missing": list(example.missing),
        },
        "fix": entry.fix,
        "fixed": None if entry.fixed is None else _show(entry.fixed),
        "autofix": entry.autofix,
    }


def codes_text() -> str:
    """One line per code: the code, its default severity and its title."""
    return "".join(f"{code.id}  {code.severity!s:<7}  {code.title}\n" for code in CODES.values())


def codes_command() -> None:
    """List every diagnostic code with its default severity and meaning."""
    typer.echo(codes_text(), nl=False)


def rule_command(code: _Code = None, format: TextOrJsonOption = TextOrJson.text) -> None:
    """Explain a diagnostic code: its severity, what Webots does, an example that triggers it,
    its fix, and whether validate --fix applies it. Without a code, list every code."""
    entries = list(RULES.values()) if code is None else [rule(code)]
    if format is TextOrJson.json:
        doc = {"schema": "motiontool.rule", "schema_version": 1}
        typer.echo(dumps({**doc, "rules": [_json(e) for e in entries]}), nl=False)
    elif code is None:
        typer.echo(codes_text(), nl=False)
    else:
        typer.echo(_text(entries[0]), nl=False)
