"""``motiontool sample``: the command stream a Webots controller sends."""

from __future__ import annotations

import csv
import enum
import io
import math
from pathlib import Path
from typing import Annotated

import typer

from motiontool.cli.jsontext import dumps
from motiontool.cli.options import MotionFile, timestep_option
from motiontool.cli.output import emit, refuse_overwrite
from motiontool.motionfmt import read_file
from motiontool.motionfmt.errors import MotionToolError
from motiontool.motionfmt.fileio import source_name
from motiontool.motionfmt.player import CommandStream, sample
from motiontool.motionfmt.reader import read_bytes
from motiontool.stamps import stamps

__all__ = ["MAX_CELLS", "SampleFormat", "sample_command"]

MAX_CELLS = 10**8
"""Most cells (steps × joints) ``sample`` writes: about 2 GB of CSV, 1 GB of arrays in memory."""

_ROWS_PER_CHUNK = 1 << 14  # rows converted to Python at once: bounds the temporary lists


class SampleFormat(enum.StrEnum):
    """What ``sample`` writes: a CSV table or a JSON document."""

    csv = "csv"
    json = "json"


def _cell(value: float, sent: bool) -> str:
    """A target as CSV text: shortest round-trip ``repr`` ('nan', 'inf', '-inf' included), or
    empty where no command is sent."""
    return repr(value) if sent else ""


def _csv(stream: CommandStream) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["time_ms", *stream.joints])
    for start in range(0, stream.elapsed_ms.shape[0], _ROWS_PER_CHUNK):
        rows = slice(start, start + _ROWS_PER_CHUNK)
        writer.writerows(
            [t, *map(_cell, values, sent)]
            for t, values, sent in zip(
                stream.elapsed_ms[rows].tolist(),
                stream.targets[rows].tolist(),
                stream.commanded[rows].tolist(),
                strict=True,
            )
        )
    return buffer.getvalue()


def _json_value(value: float, sent: bool) -> float | str | None:
    """null where no command is sent, the strings 'nan' / 'inf' / '-inf' for a non-finite
    command (JSON has no such numbers), the number otherwise."""
    if not sent:
        return None
    return value if math.isfinite(value) else repr(value)


def _json(stream: CommandStream, path: str) -> str:
    targets = [
        list(map(_json_value, values, sent))
        for values, sent in zip(stream.targets.tolist(), stream.commanded.tolist(), strict=True)
    ]
    doc = {
        "schema": "motiontool.sample",
        "schema_version": 1,
        "stamps": stamps(),
        "file": path,
        "timestep_ms": stream.timestep_ms,
        "joints": list(stream.joints),
        "units": {
            "elapsed_ms": "ms",
            "targets": "rad (m for linear joints); null = no command; 'nan', 'inf', '-inf' ="
            " a non-finite command Webots sends to the motor",
        },
        "elapsed_ms": stream.elapsed_ms.tolist(),
        "targets": targets,
    }
    return dumps(doc, indent=None, allow_nan=False)


def sample_command(
    path: MotionFile,
    timestep: Annotated[
        int, timestep_option("20, the Webots Nao worlds'; the UR5e's is 8", use="one row per step")
    ] = 20,
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
    output: Annotated[
        Path | None,
        typer.Option(
            "--output", "-o", help="Write to this file instead of stdout (never over the input)."
        ),
    ] = None,
    reverse: Annotated[bool, typer.Option("--reverse", help="Play backwards.")] = False,
    loop: Annotated[int, typer.Option("--loop", min=1, help="Play this many cycles.")] = 1,
) -> None:
    """Print the targets a Webots controller stepping every --timestep ms sends, step by step.

    One row per step (time_ms = playback time), values in radians (shortest round-trip
    spelling), an empty cell where the joint gets no command, 'nan' or 'inf' where Webots sends
    that to the motor (a nan/inf cell, or inf - inf interpolated). Bit-identical to Webots'
    player.
    """
    refuse_overwrite(output, [path], "-o")
    motion = read_bytes(read_file(path), source_name(path)).motion
    steps = (-(-motion.duration_ms // timestep) + 1) * loop
    cells = steps * motion.n_joints
    if cells > MAX_CELLS:
        raise MotionToolError(
            f"{path}: sampling {motion.duration_ms} ms every {timestep} ms for {loop} cycle(s)"
            f" gives {steps} steps x {motion.n_joints} joints = {cells} cells, above the limit"
            f" of {MAX_CELLS}; use a larger --timestep or fewer --loop cycles"
        )
    stream = sample(motion, timestep, reverse=reverse, loops=loop)
    text = _json(stream, source_name(path)) if format is SampleFormat.json else _csv(stream)
    emit(text, output)
