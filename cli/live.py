"""``play``'s live view: its options (``--connect``, ``--speed``, ``--fast``), the choice of view
they and ``--headless`` make, and the note when the viewer closes mid-run
(:mod:`motiontool.sim.live` shows the run)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Annotated, NoReturn

import typer

from motiontool import exit_codes
from motiontool.cli.options import finite
from motiontool.errors import MotionToolError
from motiontool.extras import require
from motiontool.sim.live import LiveView, has_display

if TYPE_CHECKING:
    from motiontool.sim.live import ViewerClosed

__all__ = [
    "NO_DISPLAY",
    "ConnectOption",
    "FastOption",
    "HeadlessOption",
    "SpeedOption",
    "live_view",
    "stopped",
]

HeadlessOption = Annotated[
    bool,
    typer.Option("--headless", help="Run without a view (CI); --rrd FILE records the run."),
]
ConnectOption = Annotated[
    str | None,
    typer.Option(
        "--connect",
        metavar="URL",
        help="Stream the run to a running Rerun viewer or server "
        "(rerun+http://HOST:PORT/proxy) instead of spawning a viewer.",
    ),
]
SpeedOption = Annotated[
    float | None,
    typer.Option(
        "--speed",
        callback=finite,
        help="Live view: simulated seconds per second of wall clock [default: 1, real time].",
    ),
]
FastOption = Annotated[
    bool, typer.Option("--fast", help="Live view: as fast as the machine allows, not paced.")
]

NO_DISPLAY = (
    "no display to show the run on (DISPLAY and WAYLAND_DISPLAY are unset): pass --headless to "
    "run without a view, --headless --rrd FILE to record it for later, or --connect "
    "rerun+http://HOST:PORT/proxy to stream it to a running viewer"
)


def live_view(
    headless: bool,
    connect: str | None,
    speed: float | None,
    fast: bool,
    no_display: str = NO_DISPLAY,
) -> LiveView | None:
    """The live view the options ask for (None: ``--headless``; ``no_display``: the line where
    there is neither a display nor ``--connect``).

    Raises:
        MotionToolError: options that contradict each other, a speed that is not a positive
            number, or no display to spawn a viewer on and no ``--connect``.
    """
    if headless:
        for flag, given in (("--connect", connect), ("--speed", speed), ("--fast", fast)):
            if given not in (None, False):
                raise MotionToolError(f"{flag} is for the live view; --headless runs without one")
        return None
    if fast and speed is not None:
        raise MotionToolError("--fast plays as fast as it can; --speed paces it: pass one")
    if speed is not None and not (math.isfinite(speed) and speed > 0):
        raise MotionToolError(f"--speed {speed:g}: expected a positive number (1: real time)")
    if connect is None and not has_display():
        raise MotionToolError(no_display)
    require("rerun", "rerun", "motiontool play (live view)")
    return LiveView(url=connect, speed=None if fast else (speed or 1.0))


def stopped(exc: ViewerClosed) -> NoReturn:
    """A run whose viewer closed: a note on stderr, exit 0 (the user closed it)."""
    typer.echo(f"motiontool: note: {exc}; the run stopped there (no report)", err=True)
    raise typer.Exit(exit_codes.CLEAN)
