"""``motiontool sample``: the command stream a Webots controller sends, streamed.

Rows are computed and written in chunks of a bounded number of cells
(:func:`motiontool.motionfmt.player.iter_commands`), so the first row is out at once and memory
stays flat whatever the duration; ``-o FILE`` writes a temporary file that replaces FILE when
the stream is whole (:func:`motiontool.motionfmt.fileio.open_output`).
"""

from __future__ import annotations

import enum
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated

import typer

from motiontool.cli.options import MAX_COUNT, MAX_ROWS, MotionFile, output_option, timestep_option
from motiontool.cli.output import refuse_overwrite, say_wrote
from motiontool.cli.sample_text import csv_header, csv_rows, json_document
from motiontool.cli.text import plural
from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.motionfmt import read_file
from motiontool.motionfmt.clock import clock_overflow
from motiontool.motionfmt.fileio import STDOUT, open_output, source_name
from motiontool.motionfmt.motion import Motion
from motiontool.motionfmt.player import (
    WEBOTS_DEFAULT_TIMESTEP_MS,
    iter_commands,
    iter_elapsed,
    step_count,
)
from motiontool.motionfmt.reader import ReadResult, read_bytes

__all__ = ["CHUNK_CELLS", "SampleFormat", "sample_command"]

CHUNK_CELLS = 1 << 16
"""Cells (steps × joints) computed and written at once: a few MB of text, whatever the duration."""


class SampleFormat(enum.StrEnum):
    """What ``sample`` writes: a CSV table or a JSON document."""

    csv = "csv"
    json = "json"


def _refuse_endless(result: ReadResult, timestep: int, reverse: bool) -> None:
    """A motion whose playback time wraps and never ends at this time step (MT115): its stream
    has no end to print, and a part of it would read as a motion that ends."""
    motion = result.motion
    overflow = None if reverse else clock_overflow(motion.duration_ms, timestep)
    if overflow is None or overflow.ends:
        return
    line, column, _ = result.cell_span(motion.n_poses - 1)
    raise MotionSyntaxError(
        f"{overflow.message}, so sample has no end to print; {overflow.hint} [MT115]",
        result.path,
        line,
        column,
    )


def _refuse_rows(
    name: str, motion: Motion, timestep: int, loop: int, rows: int, max_rows: int | None
) -> None:
    if max_rows is None or rows <= max_rows:
        return
    raise MotionToolError(
        f"{name}: sampling {motion.duration_ms} ms every {timestep} ms for {loop} cycle(s)"
        f" gives {rows} rows, above --max-rows {max_rows}; use a larger --timestep, fewer"
        " --loop cycles or a larger --max-rows"
    )


def _chunks(
    motion: Motion, name: str, timestep: int, format: SampleFormat, reverse: bool, loop: int
) -> Iterator[str]:
    """The output text, piece by piece."""
    chunk_steps = max(1, CHUNK_CELLS // max(1, motion.n_joints))
    stream = iter_commands(motion, timestep, reverse=reverse, loops=loop, chunk_steps=chunk_steps)
    if format is SampleFormat.csv:
        yield csv_header(motion.joints)
        yield from map(csv_rows, stream)
        return
    elapsed = iter_elapsed(
        motion.duration_ms, timestep, reverse=reverse, loops=loop, chunk_steps=chunk_steps
    )
    yield from json_document(name, timestep, motion.joints, elapsed, stream)


_Output = Annotated[
    Path | None, output_option("Write to this file instead of stdout (never over the input).")
]


def sample_command(
    path: MotionFile,
    timestep: Annotated[
        int,
        timestep_option(
            f"Webots' {WEBOTS_DEFAULT_TIMESTEP_MS}; the Nao's worlds 20, the UR5e's 8",
            use="one row per step",
        ),
    ] = WEBOTS_DEFAULT_TIMESTEP_MS,
    format: Annotated[
        SampleFormat,
        typer.Option(
            "--format",
            "-f",
            help="csv: an empty cell where no command is sent, 'nan' / 'inf' where Webots sends"
            ' one. json: null where no command is sent, the strings "nan" / "inf" / "-inf"'
            " for a non-finite command.",
        ),
    ] = SampleFormat.csv,
    output: _Output = None,
    reverse: Annotated[bool, typer.Option("--reverse", help="Play backwards.")] = False,
    loop: Annotated[
        int, typer.Option("--loop", min=1, max=MAX_COUNT, help="Play this many cycles.")
    ] = 1,
    max_rows: Annotated[
        int | None,
        typer.Option(
            "--max-rows",
            min=1,
            max=MAX_ROWS,
            help="Refuse, before writing anything, a stream of more rows (steps) than this."
            " Default: no limit (the stream is written as it is computed, in constant memory).",
            show_default=False,
        ),
    ] = None,
) -> None:
    """Print the targets a Webots controller stepping every --timestep ms sends, step by step.

    One row per step (time_ms = playback time), values in radians (shortest round-trip
    spelling), an empty cell where the joint gets no command, 'nan' or 'inf' where Webots sends
    that to the motor (a nan/inf cell, or inf - inf interpolated). Bit-identical to Webots'
    player, whose playback time is a C int: where it wraps before the motion ends the rows
    follow it (negative times, the first pose again); a motion that then never ends (MT115)
    is refused.
    """
    refuse_overwrite(output, [path], "-o")
    name = source_name(path)
    result = read_bytes(read_file(path), name)
    motion = result.motion
    _refuse_endless(result, timestep, reverse)
    rows = step_count(motion.duration_ms, timestep, reverse=reverse, loops=loop)
    if rows is not None:
        _refuse_rows(name, motion, timestep, loop, rows, max_rows)
    with open_output(STDOUT if output is None else output) as sink:
        for text in _chunks(motion, name, timestep, format, reverse, loop):
            sink.write(text.encode("utf-8", "surrogateescape"))
    if rows is not None:  # a stream that never ends is refused above
        say_wrote(output, f"{format.value.upper()}, {plural(rows, 'row')} every {timestep} ms")
