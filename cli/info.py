"""``motiontool info``: what a motion file holds."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Annotated

import typer

from motiontool.cli.options import TableFormat
from motiontool.cli.stamps import stamps
from motiontool.motionfmt.fileio import read_file
from motiontool.motionfmt.summary import MotionSummary, summarize

__all__ = ["info_command"]


def _text(s: MotionSummary) -> str:
    rows = [
        (
            "file",
            f"{s.path} ({s.size_bytes} bytes, {s.line_ends} line ends"
            f"{', final newline' if s.final_newline else ', no final newline'})",
        ),
        ("joints", f"{len(s.joints)}: {', '.join(s.joints)}"),
        ("poses", str(s.poses)),
        ("duration", f"{s.duration_ms} ms ({s.duration_ms / 1000:.3f} s)"),
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
    rows.append(("findings", f"{s.warnings} (run 'motiontool validate {s.path}')"))
    width = max(len(k) for k, _ in rows)
    return "\n".join(f"{k:<{width}}  {v}" for k, v in rows) + "\n"


def info_command(
    path: Annotated[Path, typer.Argument(help="A motion file.", show_default=False)],
    format: Annotated[
        TableFormat, typer.Option("--format", "-f", help="text or json (csv is not offered).")
    ] = TableFormat.text,
) -> None:
    """Joints, poses, duration, pose spacing and undefined cells of a motion file."""
    s = summarize(read_file(path), str(path))
    if format is TableFormat.json:
        doc = {"schema": "motiontool.info", "schema_version": 1, "stamps": stamps()}
        doc.update(dataclasses.asdict(s))
        doc["units"] = {"first_ms": "ms", "duration_ms": "ms", "spacing_ms": "ms"}
        typer.echo(json.dumps(doc, indent=2, ensure_ascii=False))
    elif format is TableFormat.csv:
        raise typer.BadParameter("info prints text or json", param_hint="--format")
    else:
        typer.echo(_text(s), nl=False)
