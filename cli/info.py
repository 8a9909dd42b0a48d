"""``motiontool info``: what a motion file holds."""

from __future__ import annotations

import dataclasses
import shlex

import typer

from motiontool.cli.jsontext import dumps
from motiontool.cli.options import MotionFile, TextOrJson, TextOrJsonOption
from motiontool.cli.text import plural
from motiontool.motionfmt.fileio import read_file, source_name
from motiontool.motionfmt.summary import MotionSummary, summarize
from motiontool.motionfmt.units import MS_PER_S
from motiontool.stamps import stamps

__all__ = ["info_command"]


def _findings(s: MotionSummary, arg: str) -> str:
    """The counts ``validate --robot none`` gives, by severity, and how to list them."""
    counts = ", ".join(
        [plural(s.errors, "error"), plural(s.warnings, "warning"), plural(s.notes, "note")]
    )
    return (
        f"{counts} (syntax only; 'motiontool validate --robot none {shlex.quote(arg)}' lists them)"
    )


def _text(s: MotionSummary, arg: str) -> str:
    rows = [
        (
            "file",
            f"{s.path} ({s.size_bytes} bytes, {s.line_ends} line ends"
            f"{', final newline' if s.final_newline else ', no final newline'})",
        ),
        ("joints", f"{len(s.joints)}: {', '.join(s.joints)}"),
        ("poses", str(s.poses)),
        ("duration", f"{s.duration_ms} ms ({s.duration_ms / MS_PER_S:.3f} s)"),
        ("first pose", f"{s.first_ms} ms"),
    ]
    if s.spacing_ms is None:
        rows.append(("spacing", "one pose"))
    elif s.uniform:
        rows.append(("spacing", f"{s.spacing_ms[0]} ms (uniform)"))
    else:
        lo, med, hi = s.spacing_ms
        rows.append(("spacing", f"min {lo} ms, median {med:g} ms, max {hi} ms"))
    star = {j: n for j, n in s.undefined.items() if n}
    total = sum(star.values())
    rows.append(
        (
            "undefined",
            f"{total} cells ('*')"
            + (": " + ", ".join(f"{j} {n}" for j, n in star.items()) if star else ""),
        )
    )
    if s.ignored_after_line is not None:
        rows.append(("ignored", f"everything after the blank line {s.ignored_after_line}"))
    rows.append(("findings", _findings(s, arg)))
    width = max(len(k) for k, _ in rows)
    return "\n".join(f"{k:<{width}}  {v}" for k, v in rows) + "\n"


def info_command(
    path: MotionFile,
    format: TextOrJsonOption = TextOrJson.text,
) -> None:
    """Joints, poses, duration, pose spacing and undefined cells of a motion file, and the
    count of what 'validate --robot none' finds in it (errors, warnings, notes)."""
    s = summarize(read_file(path), source_name(path))
    if format is TextOrJson.json:
        # schema 2: "warnings" counts warnings only (1 counted every finding), with "errors"
        # and "notes" beside it.
        doc = {"schema": "motiontool.info", "schema_version": 2, "stamps": stamps()}
        doc.update(dataclasses.asdict(s))
        doc["units"] = {"first_ms": "ms", "duration_ms": "ms", "spacing_ms": "ms"}
        typer.echo(dumps(doc), nl=False)
    else:
        typer.echo(_text(s, str(path)), nl=False)
