"""``motiontool codes``: the diagnostic codes and what they mean."""

from __future__ import annotations

import typer

from motiontool.motionfmt.diagnostics import CODES

__all__ = ["codes_command"]


def codes_command() -> None:
    """List every diagnostic code with its default severity and meaning."""
    for code in CODES.values():
        typer.echo(f"{code.id}  {code.severity!s:<7}  {code.title}")
