"""``--start``, ``--expect`` and ``--no-sidecar``: the run options of ``play`` and ``batch``
(one spelling each; the help says whether it is about one run or every run of a batch)."""

from __future__ import annotations

from typing import Any

import typer

from motiontool.sim.start import StartState

__all__ = ["NO_SIDECAR", "Start", "expect_option", "start_option"]


Start = StartState
"""``--start``'s choices: the start states (:class:`motiontool.sim.start.StartState`)."""


def start_option(sidecar_start: str) -> Any:
    """``--start``; ``sidecar_start`` says whose sidecar start is the default."""
    return typer.Option(
        "--start",
        help="Start standing, lying face down or lying face up (default: "
        f"{sidecar_start}, else standing).",
        show_default=False,
    )


def expect_option(who: str, sidecar: str) -> Any:
    """``--expect``; ``who`` must do it (``the run``, ``every run``), in addition to ``sidecar``."""
    return typer.Option(
        "--expect",
        help=f"What {who} must do, e.g. 'dx>=0.3', 'yaw=60±10', upright (repeatable; in"
        f" addition to {sidecar}).",
        show_default=False,
    )


NO_SIDECAR = typer.Option("--no-sidecar", help="Ignore motions.toml sidecars.")
"""``--no-sidecar``."""
