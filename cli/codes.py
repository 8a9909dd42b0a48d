"""``motiontool codes``: the diagnostic codes and what they mean."""

from __future__ import annotations

import typer

from motiontool.motionfmt.diagnostics import CODES

__all__ = ["codes_command", "codes_text"]


def codes_text() -> str:
    """One line per code: the code, its default severity and its title."""
    return "".join(f"{code.id}  {code.severity!s:<7}  {code.title}\n" for code in CODES.values())


def codes_command() -> None:
    """List every diagnostic code with its default severity and meaning."""
    typer.echo(codes_text(), nl=False)
