"""``motiontool trim``: keep a time window, with exact boundary poses."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from motiontool.cli import jsontext
from motiontool.cli._authoring import (
    destination,
    load_input,
    output_target,
    parse_time_ms,
    report_header,
    say,
    write_blocks,
)
from motiontool.cli.options import Format, FormatOption, InPlace, MotionFile, Output
from motiontool.motionfmt.fileio import source_name
from motiontool.motionfmt.ops.trim import Trimmed, trim

__all__ = ["trim_command"]


def trim_command(
    path: MotionFile,
    start: Annotated[
        str | None,
        typer.Option(
            "--from", help="Start of the window: ms (1500), s:ms (1:500) or m:s:ms (00:01:500)."
        ),
    ] = None,
    end: Annotated[
        str | None,
        typer.Option("--to", help="End of the window (default: the last pose), same forms."),
    ] = None,
    keep_times: Annotated[
        bool,
        typer.Option(
            "--keep-times",
            help="Keep the original times (the result then starts at --from, not at 0).",
        ),
    ] = False,
    output: Output = None,
    in_place: InPlace = False,
    format: FormatOption = Format.text,
) -> None:
    """Keep the part of a motion between --from and --to (playback times).

    Poses inside keep their lines (their times shifted so the result starts at 0, unless
    --keep-times). At a boundary without a pose, a new pose holds exactly what Webots' player
    commands there: its interpolation, bit for bit, and '*' where a segment touching '*'
    commands nothing. --to past the end is the end.
    """
    lo = None if start is None else parse_time_ms(start, "--from")
    hi = None if end is None else parse_time_ms(end, "--to")
    target = output_target(path, output, in_place)
    doc = load_input(path)
    result = trim(doc, lo, hi, keep_times=keep_times)
    write_blocks(result.blocks(), target, result.n_poses, result.duration_ms)
    report = _json if format is Format.json else _text
    say(report(result, path, target, doc.n_poses), target)


def _text(r: Trimmed, source: Path, target: Path | None, poses: int) -> str:
    dest = destination(target)
    shift = (
        f"times shifted {r.shift_ms} ms earlier (the result starts at 0 ms)"
        if r.shift_ms
        else "times kept"
    )
    return (
        f"trimmed {source_name(source)} -> {dest}: kept {r.from_ms} ms to {r.to_ms} ms\n"
        f"poses: {r.kept} of {poses} kept, {r.inserted} boundary poses inserted "
        "(Webots' interpolation there, exact)\n"
        f"{shift}; duration {r.duration_ms} ms\n"
    )


def _json(r: Trimmed, source: Path, target: Path | None, poses: int) -> str:
    doc = {
        **report_header("motiontool.trim", source, target),
        "units": {"from_ms": "ms", "to_ms": "ms", "shift_ms": "ms", "duration_ms": "ms"},
        "from_ms": r.from_ms,
        "to_ms": r.to_ms,
        "shift_ms": r.shift_ms,
        "poses": {"old": poses, "kept": r.kept, "inserted": r.inserted},
        "duration_ms": r.duration_ms,
    }
    return jsontext.dumps(doc)
