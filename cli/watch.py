"""``motiontool watch``: the authoring loop. On every save of a watched file it is validated
(printed as ``validate`` prints it) and, when clean, played into the live view as a new take
(``play``'s own command, its options passed on).

The folders of the files are watched, not the files: an editor's atomic save (write a copy,
rename it over the file), a file deleted and created again, and the several writes of one save
(grouped by :func:`watchfiles.watch` until the folder is quiet) all come as changes of the
file's path. ``watchfiles`` is the only file-watching code (the ``watch`` extra), imported here
only when the command runs.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Annotated

import typer

from motiontool import exit_codes
from motiontool.cli.chain_options import LoopOption
from motiontool.cli.live import ConnectOption, FastOption, SpeedOption, live_view
from motiontool.cli.options import Timestep, robot_option
from motiontool.cli.physics_options import WorldOption
from motiontool.cli.run_options import Start, expect_option, start_option
from motiontool.errors import MotionToolError
from motiontool.extras import require

__all__ = ["watch_command"]

_Files = Annotated[
    list[Path],
    typer.Argument(help="Motion files to check and play on every save.", show_default=False),
]
_Robot = Annotated[str | None, robot_option("Robot to check and play on (default: as play)")]
_Start = Annotated[Start | None, start_option("the sidecar's start")]
_Expect = Annotated[
    list[str] | None, expect_option("each take", "the motions.toml sidecar's, for each file")
]

_NO_DISPLAY = (
    "no display to show the takes on (DISPLAY and WAYLAND_DISPLAY are unset): pass --connect "
    "rerun+http://HOST:PORT/proxy to stream them to a running viewer (or check with validate "
    "and play --headless --rrd FILE)"
)

Take = Callable[[Path], int]
"""Check or play one file; its exit code."""


def watch_command(
    files: _Files,
    connect: ConnectOption = None,
    speed: SpeedOption = None,
    fast: FastOption = False,
    robot: _Robot = None,
    start: _Start = None,
    loop: LoopOption = None,
    expect: _Expect = None,
    timestep: Timestep = None,
    world: WorldOption = None,
) -> None:
    """Validate motion files on every save and play each clean one live as a new take.

    Findings are printed as validate prints them; a clean file is played into the live view
    (a spawned Rerun viewer, or --connect URL) as a new recording, so takes compare side by
    side, with the expectations (--expect, motions.toml) met or not. Copes with atomic saves,
    several writes per save, a half-typed file and a file deleted and created again. Runs
    until Ctrl-C (exit 130).
    """
    require("watchfiles", "watch", "motiontool watch")
    live_view(False, connect, speed, fast, _NO_DISPLAY)  # one line, before anything runs
    for f in files:
        if not f.is_file():
            raise MotionToolError(f"{f}: no such file to watch")

    def check(path: Path) -> int:
        from motiontool.cli.validate import validate_command

        return _code(lambda: validate_command([path], robot=robot, timestep=timestep))

    def take(path: Path) -> int:
        from motiontool.cli.play import play_command

        return _code(
            lambda: play_command(
                [path],
                connect=connect,
                speed=speed,
                fast=fast,
                robot=robot,
                start=start,
                loop=loop,
                expect=expect,
                timestep=timestep,
                world=world,
            )
        )

    for f in files:
        _round(f, check, take)
    for changed in _changes(files):
        for f in changed:
            _round(f, check, take)


def _round(path: Path, check: Take, take: Take) -> None:
    """Validate ``path``; play it when clean. A file that is gone is said, and waited for."""
    typer.echo(f"motiontool watch: {path}", err=True)
    if not path.is_file():
        typer.echo(f"motiontool watch: {path} is gone; waiting for it to come back", err=True)
        return
    if check(path) == exit_codes.CLEAN:
        take(path)


def _code(run: Callable[[], object]) -> int:
    """The exit code of a command run in this process: 0, its ``typer.Exit``'s, or 2 with its
    one line for a :class:`MotionToolError` (the watch goes on)."""
    try:
        run()
    except typer.Exit as exc:
        return int(exc.exit_code)
    except MotionToolError as exc:
        from motiontool.cli.options import error_line

        typer.echo(f"motiontool: error: {error_line(exc)}", err=True)
        return exit_codes.ERROR
    return exit_codes.CLEAN


def _changes(files: Iterable[Path]) -> Iterable[list[Path]]:
    """Each group of saves, as the watched files it changed (in the order given)."""
    import watchfiles

    targets = {os.path.abspath(f): f for f in files}
    folders = sorted({os.path.dirname(p) for p in targets})

    def ours(_change: watchfiles.Change, path: str) -> bool:
        return os.path.abspath(path) in targets

    for changes in watchfiles.watch(*folders, watch_filter=ours, raise_interrupt=True):
        paths = {os.path.abspath(p) for _c, p in changes}
        yield [f for p, f in targets.items() if p in paths]
