"""``motiontool sample``: the command stream a Webots controller sends."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer

from motiontool.cli.options import TableFormat
from motiontool.cli.output import emit
from motiontool.cli.stamps import stamps
from motiontool.motionfmt import read_file
from motiontool.motionfmt.player import CommandStream, sample
from motiontool.motionfmt.reader import read_bytes

__all__ = ["sample_command"]


def _csv(stream: CommandStream) -> str:
    lines = [",".join(["time_ms", *stream.joints])]
    for t, row in zip(stream.elapsed_ms.tolist(), stream.targets.tolist(), strict=True):
        cells = ["" if math.isnan(v) else repr(v) for v in row]
        lines.append(f"{t}," + ",".join(cells))
    return "\n".join(lines) + "\n"


def _json(stream: CommandStream, path: str) -> str:
    doc = {
        "schema": "motiontool.sample",
        "schema_version": 1,
        "stamps": stamps(),
        "file": path,
        "timestep_ms": stream.timestep_ms,
        "joints": list(stream.joints),
        "units": {"elapsed_ms": "ms", "targets": "rad (m for linear joints); null = no command"},
        "elapsed_ms": stream.elapsed_ms.tolist(),
        "targets": [[None if math.isnan(v) else v for v in row] for row in stream.targets.tolist()],
    }
    return json.dumps(doc, ensure_ascii=False) + "\n"


def sample_command(
    path: Annotated[Path, typer.Argument(help="A motion file.", show_default=False)],
    timestep: Annotated[
        int,
        typer.Option(
            "--timestep",
            "-t",
            min=1,
            help="Controller time step in ms (20 in the Webots Nao worlds, 8 for the UR5e).",
        ),
    ] = 20,
    format: Annotated[
        TableFormat, typer.Option("--format", "-f", help="csv or json.")
    ] = TableFormat.csv,
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write to this file instead of stdout.")
    ] = None,
    reverse: Annotated[bool, typer.Option("--reverse", help="Play backwards.")] = False,
    loop: Annotated[int, typer.Option("--loop", min=1, help="Play this many cycles.")] = 1,
) -> None:
    """Print the targets a Webots controller stepping every --timestep ms sends, step by step.

    One row per step (time_ms = playback time), values in radians (shortest round-trip
    spelling), an empty cell where the joint gets no command. Bit-identical to Webots' player.
    """
    motion = read_bytes(read_file(path), str(path)).motion
    stream = sample(motion, timestep, reverse=reverse, loops=loop)
    text = _json(stream, str(path)) if format is TableFormat.json else _csv(stream)
    emit(text, output)
