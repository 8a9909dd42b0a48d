"""``motiontool validate``: lint motion files exactly as Webots reads them."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from motiontool.cli.formats import render
from motiontool.cli.options import ReportFormat
from motiontool.cli.output import emit
from motiontool.motionfmt.validate import validate_paths

__all__ = ["validate_command"]


def validate_command(
    paths: Annotated[
        list[Path],
        typer.Argument(
            help="Motion files, or directories searched recursively for *.motion.",
            show_default=False,
        ),
    ],
    format: Annotated[
        ReportFormat,
        typer.Option("--format", "-f", help="text for people; json, sarif or github for CI."),
    ] = ReportFormat.text,
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="Write the report to this file instead of stdout."),
    ] = None,
    timestep: Annotated[
        int | None,
        typer.Option(
            "--timestep",
            min=1,
            help="Controller time step in ms: report pose times that are not a multiple of it.",
        ),
    ] = None,
    strict: Annotated[
        bool, typer.Option("--strict", help="Fail (exit 1) on warnings too, not only on errors.")
    ] = False,
    ignore: Annotated[
        list[str] | None,
        typer.Option("--ignore", help="Diagnostic code to leave out (repeat, or comma-separate)."),
    ] = None,
) -> None:
    """Check motion files as Webots reads them; every problem, with file:line:col.

    Exit code 0 when no error is found (warnings allowed unless --strict), 1 on findings,
    2 on a usage or I/O error.
    """
    codes = [c for item in ignore or [] for c in item.split(",")]
    report = validate_paths(paths, timestep_ms=timestep, ignore=codes)
    text = render(report, format.value)
    if format is ReportFormat.text and output is None:
        typer.echo(text, nl=False)
    else:
        emit(text, output)
    if report.failed(strict=strict):
        raise typer.Exit(1)
